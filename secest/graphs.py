"""Communication graphs, consensus weights and Laplacians.

Graphs are handled as dense 0/1 adjacency matrices ``A`` with ``A[i, j] = 1``
when node ``i`` receives from node ``j`` (``j`` is an in-neighbour of ``i``);
the diagonal is zero. networkx builds and checks them.
"""

from __future__ import annotations

import networkx as nx
import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.validation import ValidationError, as_matrix, check_positive_int

__all__ = [
    "adjacency",
    "algebraic_connectivity",
    "check_connected",
    "complete_graph",
    "laplacian",
    "neighbours",
    "random_geometric_graph",
    "ring_graph",
    "row_stochastic_weights",
    "check_row_stochastic",
]


def adjacency(graph: nx.Graph | nx.DiGraph) -> NDArray[np.float64]:
    """Dense 0/1 adjacency matrix of a networkx graph, nodes in sorted order.

    For a directed graph, ``A[i, j] = 1`` if the edge ``j -> i`` exists, so row
    ``i`` lists the in-neighbours whose data node ``i`` receives. Self-loops are
    dropped.
    """
    if not isinstance(graph, nx.Graph):
        raise ValidationError(f"graph must be a networkx Graph or DiGraph, found {type(graph).__name__}")
    nodes = sorted(graph.nodes)
    a = nx.to_numpy_array(graph, nodelist=nodes, weight=None, dtype=float)
    if graph.is_directed():
        a = a.T
    np.fill_diagonal(a, 0.0)
    return (a != 0).astype(float)


def _check_adjacency(name: str, adj: ArrayLike) -> NDArray[np.float64]:
    a = as_matrix(name, adj, square=True)
    if not np.all((a == 0) | (a == 1)):
        raise ValidationError(f"{name} must contain only 0 and 1 entries")
    if np.any(np.diag(a) != 0):
        raise ValidationError(f"{name} must have a zero diagonal (no self-loops)")
    return a


def ring_graph(n: int) -> NDArray[np.float64]:
    """Adjacency of the undirected ring (cycle) on ``n >= 3`` nodes."""
    n = check_positive_int("n", n, minimum=3)
    return adjacency(nx.cycle_graph(n))


def complete_graph(n: int) -> NDArray[np.float64]:
    """Adjacency of the all-to-all graph on ``n >= 2`` nodes."""
    n = check_positive_int("n", n, minimum=2)
    return adjacency(nx.complete_graph(n))


def random_geometric_graph(
    n: int, radius: float, seed: int, *, max_tries: int = 1000, return_positions: bool = False
) -> NDArray[np.float64] | tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Connected random geometric graph on the unit square.

    Nodes are placed uniformly at random and joined when closer than
    ``radius``; placements are redrawn (deterministically from ``seed``) until
    the graph is connected.

    Returns
    -------
    adj : (n, n) ndarray
        0/1 adjacency.
    positions : (n, 2) ndarray
        Node positions, only if ``return_positions`` (for plotting the deployment).

    Raises
    ------
    ValidationError
        If no connected placement is found in ``max_tries`` draws (radius too small).
    """
    n = check_positive_int("n", n, minimum=2)
    if not radius > 0:
        raise ValidationError(f"radius must be positive, found {radius!r}")
    rng = np.random.default_rng(seed)
    for _ in range(max_tries):
        xy = rng.random((n, 2))
        g = nx.random_geometric_graph(n, radius, pos={i: tuple(p) for i, p in enumerate(xy)})
        if nx.is_connected(g):
            return (adjacency(g), xy) if return_positions else adjacency(g)
    raise ValidationError(f"radius={radius} gave no connected graph on n={n} nodes in {max_tries} draws")


def check_connected(adj: ArrayLike, *, strongly: bool = True) -> NDArray[np.float64]:
    """Check that the graph of ``adj`` is connected.

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency, ``adj[i, j] = 1`` if ``i`` receives from ``j``.
    strongly : bool, default True
        For a non-symmetric ``adj`` require strong connectivity; otherwise weak.

    Returns
    -------
    ndarray
        The validated adjacency.

    Raises
    ------
    ValidationError
        If the graph is disconnected; the message lists the components.
    """
    a = _check_adjacency("adj", adj)
    if np.array_equal(a, a.T):
        g = nx.from_numpy_array(a)
        comps = list(nx.connected_components(g))
    else:
        g = nx.from_numpy_array(a.T, create_using=nx.DiGraph)
        comps = list(
            nx.strongly_connected_components(g) if strongly else nx.weakly_connected_components(g)
        )
    if len(comps) > 1:
        shown = sorted(sorted(c) for c in comps)
        raise ValidationError(
            f"adj describes a disconnected graph with {len(comps)} components: {shown}"
        )
    return a


def neighbours(adj: ArrayLike, *, include_self: bool = False) -> list[NDArray[np.intp]]:
    """In-neighbour index lists ``N_i`` (with ``i`` itself if ``include_self``)."""
    a = _check_adjacency("adj", adj)
    if include_self:
        a = a + np.eye(a.shape[0])
    return [np.flatnonzero(row) for row in a]


def row_stochastic_weights(adj: ArrayLike, *, self_weight: bool = True) -> NDArray[np.float64]:
    """Uniform row-stochastic weights ``h_ij = 1/|N_i|``.

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency with zero diagonal.
    self_weight : bool, default True
        Count node ``i`` in its own neighbourhood ``N_i`` (``h_ii = 1/|N_i|``);
        otherwise ``h_ii = 0`` and every node must have a neighbour.

    Raises
    ------
    ValidationError
        If a node has no neighbour and ``self_weight`` is False.
    """
    a = _check_adjacency("adj", adj)
    if self_weight:
        a = a + np.eye(a.shape[0])
    deg = a.sum(axis=1)
    if np.any(deg == 0):
        isolated = np.flatnonzero(deg == 0).tolist()
        raise ValidationError(f"adj has nodes without neighbours {isolated}: weights undefined")
    return a / deg[:, None]


def check_row_stochastic(weights: ArrayLike, *, tol: float = 1e-12) -> NDArray[np.float64]:
    """Check that ``weights`` is non-negative with rows summing to one.

    Raises
    ------
    ValidationError
        Naming the first offending row.
    """
    w = as_matrix("weights", weights, square=True)
    if np.any(w < -tol):
        i, j = np.argwhere(w < -tol)[0]
        raise ValidationError(f"weights must be non-negative, found weights[{i}, {j}] = {w[i, j]}")
    sums = w.sum(axis=1)
    bad = np.flatnonzero(np.abs(sums - 1.0) > tol)
    if bad.size:
        raise ValidationError(f"weights must be row-stochastic, row {bad[0]} sums to {sums[bad[0]]:.6g}")
    return w


def laplacian(adj: ArrayLike) -> NDArray[np.float64]:
    """Graph Laplacian ``L = D - A`` with ``D`` the diagonal of row sums (in-degrees)."""
    a = _check_adjacency("adj", adj)
    return np.diag(a.sum(axis=1)) - a


def algebraic_connectivity(adj: ArrayLike) -> float:
    """Second-smallest Laplacian eigenvalue ``lambda_2(L)`` of an undirected graph.

    Raises
    ------
    ValidationError
        If ``adj`` is not symmetric or the graph is disconnected (``lambda_2 = 0``).
    """
    a = _check_adjacency("adj", adj)
    if not np.array_equal(a, a.T):
        raise ValidationError("adj must be symmetric (undirected graph) for lambda_2")
    check_connected(a)
    return float(np.linalg.eigvalsh(laplacian(a))[1])

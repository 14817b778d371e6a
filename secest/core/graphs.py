"""Communication graphs, consensus weights and Laplacians.

Graphs are handled as dense 0/1 adjacency matrices ``A`` with ``A[i, j] = 1``
when node ``i`` receives from node ``j`` (``j`` is an in-neighbour of ``i``);
the diagonal is zero, so a neighbourhood ``N_i`` never contains ``i`` itself
(as in ding2020, Section II). networkx converts graphs, scipy checks connectivity.
Dense ``N x N`` matrices are limited to ``N <= secest.core.validation.MAX_DENSE_NODES``.

Large sparse networks are handled as **edge lists** instead: an ``(E, 2)`` int array of
``(receiver i, sender j)`` pairs, sorted by receiver then sender, without self loops
(:func:`edge_list`, :func:`ring_edges`, :func:`complete_edges`, :func:`random_geometric_edges`,
:func:`check_connected_edges`); their size is bounded by ``MAX_ELEMENTS`` entries, not by ``N^2``.
"""

from __future__ import annotations

import networkx as nx
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csgraph, csr_array
from scipy.spatial import cKDTree

from secest.core import validation as V
from secest.core.validation import ValidationError, as_matrix

__all__ = [
    "adjacency",
    "algebraic_connectivity",
    "check_connected",
    "check_connected_edges",
    "check_row_stochastic",
    "complete_edges",
    "complete_graph",
    "edge_list",
    "laplacian",
    "neighbours",
    "random_geometric_edges",
    "random_geometric_graph",
    "ring_edges",
    "ring_graph",
    "row_stochastic_weights",
]


def _check_nodes(name: str, n: int, minimum: int) -> int:
    n = V.check_int(name, n, minimum=minimum)
    V.check_size(name, n, V.MAX_DENSE_NODES, "nodes of a dense adjacency matrix")
    return n


def adjacency(graph: nx.Graph | nx.DiGraph) -> NDArray[np.float64]:
    """Dense 0/1 adjacency matrix of a networkx graph, nodes in sorted order.

    For a directed graph, ``A[i, j] = 1`` if the edge ``j -> i`` exists, so row
    ``i`` lists the in-neighbours whose data node ``i`` receives. Self-loops are
    dropped.

    Parameters
    ----------
    graph : networkx.Graph or networkx.DiGraph
        At least one node, sortable node labels.

    Returns
    -------
    (N, N) ndarray
        0/1 adjacency with zero diagonal.

    Raises
    ------
    ValidationError
        If ``graph`` is not a networkx graph, is empty, has unsortable labels or too many nodes.
    """
    if not isinstance(graph, nx.Graph):
        raise ValidationError(f"graph must be a networkx Graph or DiGraph, found {type(graph).__name__}")
    _check_nodes("graph (number of nodes)", graph.number_of_nodes(), 1)
    try:
        nodes = sorted(graph.nodes)
    except TypeError as exc:
        raise ValidationError("graph must have mutually comparable (sortable) node labels") from exc
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
    """Adjacency of the undirected ring (cycle) on ``n`` nodes.

    Parameters
    ----------
    n : int
        Number of nodes, ``3 <= n <= MAX_DENSE_NODES``.

    Returns
    -------
    (n, n) ndarray
    """
    n = _check_nodes("n", n, 3)
    a = np.zeros((n, n))
    i = np.arange(n)
    a[i, (i + 1) % n] = a[(i + 1) % n, i] = 1.0
    return a


def complete_graph(n: int) -> NDArray[np.float64]:
    """Adjacency of the all-to-all graph on ``n`` nodes.

    Parameters
    ----------
    n : int
        Number of nodes, ``2 <= n <= MAX_DENSE_NODES``.

    Returns
    -------
    (n, n) ndarray
    """
    n = _check_nodes("n", n, 2)
    return np.ones((n, n)) - np.eye(n)


def random_geometric_graph(
    n: int,
    radius: float,
    seed: int | np.random.Generator,
    *,
    max_tries: int = 1000,
    return_positions: bool = False,
) -> NDArray[np.float64] | tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Connected random geometric graph on the unit square.

    Nodes are placed uniformly at random and joined when at distance at most
    ``radius`` (as ``networkx.random_geometric_graph``); placements are redrawn
    (deterministically from ``seed``) until the graph is connected: the dense form of
    :func:`random_geometric_edges` (the same draws, the same graph).

    Parameters
    ----------
    n : int
        Number of nodes, ``2 <= n <= MAX_DENSE_NODES``.
    radius : float
        Connection radius, positive.
    seed : int or numpy.random.Generator
        Seed (non-negative integer) or generator of the placements; ``None`` is refused.
    max_tries : int, default 1000
        Placements drawn before giving up; ``n * max_tries <= MAX_STEPS``.
    return_positions : bool, default False
        Also return the node positions.

    Returns
    -------
    adj : (n, n) ndarray
        0/1 adjacency.
    positions : (n, 2) ndarray
        Node positions, only if ``return_positions`` (for plotting the deployment).

    Raises
    ------
    ValidationError
        On bad arguments, or if no connected placement is found in ``max_tries`` draws
        (radius too small).
    """
    n = _check_nodes("n", n, 2)
    edges, xy = random_geometric_edges(n, radius, seed, max_tries=max_tries, return_positions=True)
    a = np.zeros((n, n))
    a[edges[:, 0], edges[:, 1]] = 1.0
    return (a, xy) if V.check_bool("return_positions", return_positions) else a


def _components(a: NDArray[np.float64], strongly: bool) -> list[list[int]]:
    symmetric = np.array_equal(a, a.T)
    kind = "strong" if strongly and not symmetric else "weak"
    count, labels = csgraph.connected_components(a, directed=not symmetric, connection=kind)
    return sorted(np.flatnonzero(labels == c).tolist() for c in range(count))


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
    strongly = V.check_bool("strongly", strongly)
    comps = _components(a, strongly)
    if len(comps) > 1:
        shown = comps if len(comps) <= 10 else [*comps[:10], "..."]
        raise ValidationError(
            f"adj describes a disconnected graph with {len(comps)} components: {shown}"
        )
    return a


def neighbours(adj: ArrayLike, *, include_self: bool = False) -> list[NDArray[np.intp]]:
    """In-neighbour index lists ``N_i`` (with ``i`` itself if ``include_self``).

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency with zero diagonal.
    include_self : bool, default False
        Add ``i`` to its own list.

    Returns
    -------
    list of ndarray of int
        ``N_i`` in increasing order, one array per node.
    """
    a = _check_adjacency("adj", adj)
    if V.check_bool("include_self", include_self):
        a = a + np.eye(a.shape[0])
    return [np.flatnonzero(row) for row in a]


def row_stochastic_weights(adj: ArrayLike, *, self_weight: bool = False) -> NDArray[np.float64]:
    """Uniform row-stochastic weights ``h_ij = 1/|N_i|`` on the edges.

    The default (``h_ii = 0``, every row summing to one over ``N_i``) is the weight matrix of
    ding2020 (Section II, Section V) that :func:`secest.methods.ding2020.secure_filter_step` expects.

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency with zero diagonal.
    self_weight : bool, default False
        Count node ``i`` in its own neighbourhood (``h_ii = h_ij = 1/(|N_i| + 1)``);
        otherwise ``h_ii = 0`` and every node must have a neighbour.

    Returns
    -------
    (N, N) ndarray
        Row-stochastic weights.

    Raises
    ------
    ValidationError
        If a node has no neighbour and ``self_weight`` is False.
    """
    a = _check_adjacency("adj", adj)
    if V.check_bool("self_weight", self_weight):
        a = a + np.eye(a.shape[0])
    deg = a.sum(axis=1)
    if np.any(deg == 0):
        isolated = np.flatnonzero(deg == 0).tolist()
        raise ValidationError(f"adj has nodes without neighbours {isolated}: weights undefined")
    return a / deg[:, None]


def check_row_stochastic(weights: ArrayLike, *, tol: float = V.RTOL) -> NDArray[np.float64]:
    """Check that ``weights`` is non-negative with rows summing to one.

    Parameters
    ----------
    weights : array_like, shape (N, N)
        Weight matrix.
    tol : float, default secest.core.validation.RTOL
        Relative tolerance of the row sums (rule in :mod:`secest.core.validation`).

    Returns
    -------
    ndarray

    Raises
    ------
    ValidationError
        Naming the first offending entry or row.
    """
    return V.check_row_stochastic("weights", weights, tol=tol)


def laplacian(adj: ArrayLike) -> NDArray[np.float64]:
    """Graph Laplacian ``L = D - A`` with ``D`` the diagonal of row sums (in-degrees).

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency with zero diagonal.

    Returns
    -------
    (N, N) ndarray
    """
    a = _check_adjacency("adj", adj)
    return np.diag(a.sum(axis=1)) - a


def algebraic_connectivity(adj: ArrayLike) -> float:
    """Second-smallest Laplacian eigenvalue ``lambda_2(L)`` of a connected undirected graph.

    Parameters
    ----------
    adj : array_like, shape (N, N)
        Symmetric 0/1 adjacency with zero diagonal, ``N >= 2``.

    Returns
    -------
    float

    Raises
    ------
    ValidationError
        If ``adj`` is not symmetric, has fewer than 2 nodes or the graph is disconnected
        (``lambda_2 = 0``).
    """
    a = _check_adjacency("adj", adj)
    if a.shape[0] < 2:
        raise ValidationError(f"adj must have at least 2 nodes for lambda_2, found {a.shape[0]}")
    if not np.array_equal(a, a.T):
        raise ValidationError("adj must be symmetric (undirected graph) for lambda_2")
    check_connected(a)
    return float(np.linalg.eigvalsh(laplacian(a))[1])


# ---------------------------------------------------------------------------------- edge lists


def _check_sparse_nodes(name: str, n: int, minimum: int) -> int:
    n = V.check_int(name, n, minimum=minimum)
    V.check_size(name, n, V.MAX_ELEMENTS, "nodes of an edge list")
    return n


def _sorted_edges(receivers: ArrayLike, senders: ArrayLike) -> NDArray[np.intp]:
    """``(E, 2)`` of unique (receiver, sender) pairs, sorted by receiver then sender."""
    e = np.column_stack([np.asarray(receivers, np.intp), np.asarray(senders, np.intp)])
    return np.unique(e, axis=0) if e.size else e.reshape(0, 2)


def edge_list(adj: ArrayLike) -> NDArray[np.intp]:
    """Edge list of a dense 0/1 adjacency: its ``(receiver i, sender j)`` pairs.

    Parameters
    ----------
    adj : array_like, shape (N, N)
        0/1 adjacency with zero diagonal, ``adj[i, j] = 1`` if ``i`` receives from ``j``.

    Returns
    -------
    (E, 2) int ndarray
        The pairs ``(i, j)`` with ``adj[i, j] = 1``, sorted by receiver then sender.
    """
    a = _check_adjacency("adj", adj)
    return np.argwhere(a > 0).astype(np.intp)


def ring_edges(n: int, degree: int = 2) -> NDArray[np.intp]:
    """Edge list of the undirected ring lattice: every node linked to ``degree / 2`` on each side.

    Parameters
    ----------
    n : int
        Number of nodes, ``>= 3`` and at most ``MAX_ELEMENTS``.
    degree : int, default 2
        Even degree of every node, ``2 <= degree < n``.

    Returns
    -------
    (n degree, 2) int ndarray
        Sorted by receiver then sender.
    """
    n = _check_sparse_nodes("n", n, 3)
    degree = V.check_int("degree", degree, minimum=2)
    if degree % 2 or degree >= n:
        raise ValidationError(f"degree must be even and below n = {n}, found {degree}")
    V.check_size("n * degree", n * degree, V.MAX_ELEMENTS, "edges of an edge list")
    shifts = np.concatenate([np.arange(1, degree // 2 + 1), -np.arange(1, degree // 2 + 1)])
    i = np.repeat(np.arange(n), shifts.size)
    return _sorted_edges(i, (i + np.tile(shifts, n)) % n)


def complete_edges(n: int) -> NDArray[np.intp]:
    """Edge list of the all-to-all graph on ``n`` nodes.

    Parameters
    ----------
    n : int
        Number of nodes, ``>= 2``, with ``n (n - 1) <= MAX_ELEMENTS``.

    Returns
    -------
    (n (n - 1), 2) int ndarray
        Sorted by receiver then sender.
    """
    n = _check_sparse_nodes("n", n, 2)
    V.check_size("n * (n - 1)", n * (n - 1), V.MAX_ELEMENTS, "edges of an edge list")
    i, j = np.divmod(np.arange(n * n), n)
    keep = i != j
    return np.column_stack([i[keep], j[keep]]).astype(np.intp)


def random_geometric_edges(
    n: int,
    radius: float,
    seed: int | np.random.Generator,
    *,
    max_tries: int = 1000,
    return_positions: bool = False,
) -> NDArray[np.intp] | tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Edge list of a connected random geometric graph on the unit square (a KD-tree, no N x N).

    Nodes are placed uniformly at random and joined when at distance at most ``radius``
    (``scipy.spatial.cKDTree.query_pairs``); placements are redrawn (deterministically from
    ``seed``) until the graph is connected (``scipy.sparse.csgraph``). The same draws and graph
    as :func:`random_geometric_graph`.

    Parameters
    ----------
    n : int
        Number of nodes, ``2 <= n <= MAX_ELEMENTS``.
    radius : float
        Connection radius, positive; the expected number of edges ``n^2 min(1, pi radius^2)``
        must not exceed ``MAX_ELEMENTS``.
    seed : int or numpy.random.Generator
        Seed (non-negative integer) or generator of the placements; ``None`` is refused.
    max_tries : int, default 1000
        Placements drawn before giving up; ``n * max_tries <= MAX_STEPS``.
    return_positions : bool, default False
        Also return the node positions.

    Returns
    -------
    edges : (E, 2) int ndarray
        Symmetric edge list sorted by receiver then sender.
    positions : (n, 2) ndarray
        Node positions, only if ``return_positions``.

    Raises
    ------
    ValidationError
        On bad arguments, or if no connected placement is found in ``max_tries`` draws.
    """
    n = _check_sparse_nodes("n", n, 2)
    radius = V.check_real("radius", radius, lower=0.0, lower_open=True)
    V.check_size("n^2 min(1, pi radius^2)", int(n * n * min(1.0, np.pi * radius**2)),
                 V.MAX_ELEMENTS, "expected edges of a random geometric graph")
    rng = V.as_rng("seed", seed)
    max_tries = V.check_int("max_tries", max_tries, minimum=1)
    V.check_size("n * max_tries", n * max_tries, V.MAX_STEPS, "node placements")
    return_positions = V.check_bool("return_positions", return_positions)
    for _ in range(max_tries):
        xy = rng.random((n, 2))
        pairs = cKDTree(xy).query_pairs(radius, 2, output_type="ndarray")
        edges = _sorted_edges(np.concatenate([pairs[:, 0], pairs[:, 1]]),
                              np.concatenate([pairs[:, 1], pairs[:, 0]]))
        if _count_components(edges, n, strongly=False) == 1:
            return (edges, xy) if return_positions else edges
    raise ValidationError(
        f"radius = {radius:g} gave no connected graph on n = {n} nodes in max_tries = {max_tries} "
        "draws: increase radius or max_tries"
    )


def _count_components(edges: NDArray[np.intp], n: int, *, strongly: bool) -> int:
    a = csr_array((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    return csgraph.connected_components(a, directed=True, connection="strong" if strongly else "weak",
                                        return_labels=False)


def check_connected_edges(edges: ArrayLike, n: int, *, strongly: bool = True) -> NDArray[np.intp]:
    """Check an edge list: pairs of nodes in ``range(n)``, sorted, unique, no self loop, connected.

    Parameters
    ----------
    edges : array_like, shape (E, 2)
        ``(receiver i, sender j)`` pairs, sorted by receiver then sender.
    n : int
        Number of nodes, ``>= 1``.
    strongly : bool, default True
        Require strong connectivity (weak connectivity otherwise); for a symmetric edge list
        the two coincide.

    Returns
    -------
    (E, 2) int ndarray
        The validated edge list.

    Raises
    ------
    ValidationError
        Naming what is wrong: shape, range, order, a self loop, or the number of components.
    """
    n = _check_sparse_nodes("n", n, 1)
    strongly = V.check_bool("strongly", strongly)
    e = np.asarray(edges)
    if e.ndim != 2 or e.shape[1] != 2 or not (e.size == 0 or np.issubdtype(e.dtype, np.integer)):
        raise ValidationError(f"edges must be an (E, 2) integer array of (receiver, sender) pairs, "
                              f"found shape {e.shape} and dtype {e.dtype}")
    e = e.astype(np.intp)
    if e.size and (e.min() < 0 or e.max() >= n):
        raise ValidationError(f"edges must name nodes in range({n}), found {e.min()} .. {e.max()}")
    if np.any(e[:, 0] == e[:, 1]):
        raise ValidationError("edges must have no self loop (receiver == sender)")
    key = e[:, 0] * n + e[:, 1]
    if np.any(np.diff(key) <= 0):
        raise ValidationError("edges must be unique and sorted by receiver then sender")
    count = _count_components(e, n, strongly=strongly) if n > 1 else 1
    if count > 1:
        raise ValidationError(f"edges describe a disconnected graph with {count} components")
    return e

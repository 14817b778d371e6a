# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # arena — every estimator against every attack, on shared plants
#
# **Beyond the papers.** The five paper notebooks reproduce each estimator on its own paper's
# example. Here every estimator meets every other on common ground: three plants, each observed
# by its sensor network (the *scenario cards* of `secest/arena/cards.toml`), under no attack and four
# attacks — a persistent sensor bias, a Bernoulli replacement of a sensor's data, falsified
# messages between nodes, and a denial of service of the links — with the same Monte Carlo runs
# fed to every method. Next to the papers' methods run the baselines a reviewer expects: the
# **oracle** (a centralised Kalman filter fed the clean data: the unit of every score), the same
# filter fed the attacked data (`kf`), a centralised filter with a chi-square bad-data detector
# (`chi2-kf`), every node alone (`local-kf`, no communication), three distributed filters with the
# papers' budget of one exchange per step (`consensus-kf-1`, consensus on information;
# `diffusion-kf`; `kcf`, Olfati-Saber's Kalman consensus filter), one with five consensus rounds
# per step (`consensus-kf`), and a Byzantine-resilient one (`wmsr-kf`, trimmed consensus).
#
# **Every method runs in every cell.** A cell outside a method's theory (its attack model, its
# noise model, its graph assumptions) is scored and *marked*; `N/A` only where a method cannot run
# at all (one rule for every method: `Method.requirements`). Scores are **unit-free** (the error
# whitened by the oracle's error covariance: 1 is the oracle on every plant), measured on each
# plant's **steady window** (after five of its time constants; the horizon is twenty), with the
# transient reported beside it, and a cell whose error **grows** is `diverged`, never a ratio.
# The falsified messages are **one attack for every method**: the state estimate a node sends is
# shifted by 20 of the oracle's steady-state standard deviations, each method's message carrying
# that shift in its own encoding.
#
# **Status of this design** (issue #28): the scores, windows, divergence rule, attacks,
# applicability rule and baselines above are implemented; the pre-registered tuning protocol
# (`secest/arena/protocol.toml`: validation seeds 101–104, test seeds 201–208) is **not yet run**:
# every row below is the method *as its paper printed it* (or a baseline's textbook default), on
# the cards' seed 2026, which is neither a validation nor a test seed. Tuned rows, the test-seed
# results and the sweep of this design over its declared space come next; the findings below are
# therefore about the printed settings only, at one draw of the runs.
#
# **What it finds** at the printed settings, seed 2026 (claims X1–X8 below, per plant; *home* is
# the plant of a method's own paper example; upper 95 % bounds of the steady-window score):
#
# * **Without attack** (X2) no paper method is within a factor 2 on every plant. guo2023 and li2025
#   are within 2 on the three-inertia plant (1.18, 1.19) and li2025 on the tank (1.45, guo2023
#   1.73); on the target plant guo2023 reaches 3.6, li2025 14.6. ding2020 scores 76 on its **home**
#   target and *diverges* on the three-inertia plant (its error grows by a factor 7·10²¹ between the
#   second and the last quarter of the window); lee2020 scores 2.5 on its **home** three-inertia
#   plant and diverges on the target (growth 9.5); ma2021 scores 12–92. The one-exchange baselines
#   set the bar: `consensus-kf-1` 3.9 / 1.18 / 1.73 (target / three-inertia / tank), `diffusion-kf`
#   52 / 1.34 / 2.9; five rounds (`consensus-kf`) 1.27 / 1.01 / 1.05; every node alone (`local-kf`)
#   72 / 20 / 10.
# * **Every attack card is felt** by the undefended baseline it reaches, on every plant (X3), and
#   under none of the four attacks is a paper method within a factor 2 on every plant (X4); the
#   replacement card makes most methods diverge on the target plant, whose state drifts away from
#   the replaced values. ma2021's estimate is the same with and without falsified messages (its
#   gains on what neighbours send are zero).
# * **Detectors** (X6, X7): guo2023 keeps its false alarms below 1 % everywhere and flags at least
#   81 % of the attacked samples; lee2020 raises up to 2.8 % false alarms (falsified messages on the
#   tank); ding2020 and `chi2-kf` miss most of the bias on the target plant.
# * **Applicability** (X5): every paper method runs in every cell; the cells outside each method's
#   theory are marked (lee2020: all 15, its model is noise-free); `kcf` cannot run on the target
#   network (ε = 0.2 times its largest degree, 10, is not below 1).
#
# Everything here is ours: no paper makes these comparisons, and each method is *read* on
# scenarios its paper did not consider (how, in the section on limitations). The findings are
# measurements with rules stated before the run, not rankings: a method that loses here may win
# on its own paper's setting, which its notebook reproduces.

# %% tags=["parameters"]
mode = "paper"  # "paper": the cards' runs and horizons; "fast": at most 3 runs of 10 steps (tests) (ours)
runs = 40  # Monte Carlo runs per scenario, shared by every method (ours)
horizon = None  # steps per run; None: each plant's own, 20 of its time constants (ours)
seed = 2026  # root of SeedSequence for truth, noises, attacks, channel (ours)
attack_scale = 1.0  # factor on every attack card's magnitude (ours)
networks = None  # networks crossed in the matrix; None: the cards' [matrix] list (ours)
attacks = None  # attacks crossed in the matrix; None: the cards' [matrix] list (ours)
methods = None  # methods scored; None: every registered method (ours)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/arena"
results_path = "figures/arena/claims.json"

# %%
import json
import re
import warnings

import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown, display
from matplotlib.patches import Patch
from matplotlib.ticker import FuncFormatter, LogFormatterSciNotation, NullFormatter

from secest.arena import matrix, report, scenarios
from secest.arena.estimators import METHODS
from secest.core.validation import ValidationError
from secest.repro import plotting, results, spaces

print(results.environment_summary())
# the methods' warnings name what went wrong, not where the repository is checked out
warnings.formatwarning = lambda message, category, *_, **__: f"{category.__name__}: {message}\n"

run = results.Run("arena", globals())
# fast mode (tests): a budget at which every code path still runs: 3 runs (a bootstrap interval
# that is not a single value), 10 steps (windows of 5 steps: a smoke test, no steady state)
runs_used = runs if mode == "paper" else min(runs, 3)
horizon_used = ("auto" if horizon is None else horizon) if mode == "paper" else min(horizon or 10, 10)
SHORT = mode == "fast"  # the windows mean nothing about a steady state at 10 steps
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)
method_names = list(METHODS) if methods is None else list(methods)
unknown = [m for m in method_names if m not in METHODS]
if unknown:
    raise ValidationError(f"parameter methods: {unknown} are not registered; registered: {list(METHODS)}")
if "oracle" not in method_names:
    method_names.insert(0, "oracle")  # the reference of every ratio is always scored
SCENARIOS = [matrix.scaled(sc, attack_scale) for sc in scenarios.matrix(
    networks=networks, attacks=attacks, runs=runs_used, horizon=horizon_used, seed=seed)]
CARDS = scenarios.cards()
HORIZONS = {sc.network.name: sc.horizon for sc in SCENARIOS}
print(f"{len(SCENARIOS)} scenarios x {len(method_names)} methods, {runs_used} runs each, horizons "
      + ", ".join(f"{n}: {k} steps" for n, k in HORIZONS.items())
      + f", seed {seed}, attack magnitudes x {attack_scale:g}")

# %% [markdown]
# ## How to read the arena
#
# **One trial per scenario.** `secest.arena.scenarios.simulate` draws the runs of a scenario once — the
# truth $x_k$, every sensor's noise, the attack, the channel — and every method estimates from that
# same draw. Differences between two methods in a scenario are therefore differences between the
# methods, not between draws (paired comparison). Changing the attack leaves the truth and the
# noises unchanged (common random numbers across an attack column of one plant).
#
# **A unit-free score.** With $e_{r,k,i}=\hat x_{i,k}-x_k$ the error of node $i$ at step $k$ of run
# $r$ and $\Sigma_o$ the oracle's error covariance pooled over the runs and the window, the
# squared error $q_{r,k,i}=e^\top\Sigma_o^{-1}e/n$ does not change under any change of state
# coordinates, so position and acceleration, angles and rates, centimetres and volts weigh the
# same; the oracle's mean $q$ is exactly 1. A node's score is $\sqrt{\text{mean}_{r,k}\,q}$, the
# network score the mean over nodes (the worst node beside it), with a 95 % percentile
# bootstrap over runs (`secest.arena.estimators.score`).
#
# **Windows from each plant's own time scale.** $\tau$ is the slower of the oracle's error decay,
# $-1/\ln\rho((I-KC)A)$ steps, and the plant's slowest decaying open-loop mode (what a node that
# does not see a mode waits for; `secest.arena.scenarios.steady_state`). The transient window is
# $[0,5\tau)$, the steady window $[5\tau,K]$, and the horizon is $K=20\tau$ (rounded up to ten
# steps): each plant runs as long as it needs. Findings cite the steady window.
#
# **Divergence by growth.** A cell is `diverged` when its mean $q$ over the last quarter of the
# steady window exceeds 4 times that of its second quarter (its RMS error doubled), or when an
# estimate is not finite: it shows the growth factor, never a score.
#
# **One attack for all.** Sensor attacks are in units of the attacked sensor's noise; a falsified
# message shifts the state estimate a node sends by `magnitude` oracle steady-state standard
# deviations per component (random signs), and each method's message carries that shift in its own
# encoding (an information vector by $Y_j\delta$, a relayed measurement by $C_j\delta$, an
# innovation by $-C_j\delta$: `Trial.received`).
#
# **Detection and false alarms** (methods with a detector): the fraction of attacked (run, step,
# node) samples of the steady window flagged, and of clean ones flagged. A node's data count as
# attacked only under the sensor attacks; alarms under falsified messages or lost links count as
# false alarms. The 95 % interval is the union of the Wilson interval and a bootstrap over runs.
#
# **Marks and N/A.** A cell outside a method's theory (`Method.conditions`) is scored and marked
# with the failed conditions; `N/A` names the requirement without which the method cannot run
# (`Method.requirements`), the same rule for every method.

# %% [markdown]
# ## Parameter provenance
#
# Every parameter of this notebook with its admissible values, its tag, the declared space that
# `make robustness` sweeps and the reason (from `notebooks/arena.toml`, fixed and committed
# before the first result was looked at):

# %%
display(Markdown(spaces.provenance_markdown("arena")))

# %% [markdown]
# ## The scenarios
#
# Generated from the cards (`secest/arena/cards.toml`): a new plant, network or attack is one table
# there; a new scenario outside the cross is one `[scenario.<name>]` table. Attack magnitudes are
# in units of the attacked output's noise standard deviation (bias, replacement) or of the oracle's
# steady-state error standard deviation of each state component (messages), so one card means the
# same on every plant and for every method; the table shows them after `attack_scale`, and each
# plant's time constant and horizon.


# %%
def md(text: object) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def attack_parameters(att: scenarios.Attack) -> str:
    """The parameters an attack card sets, in words."""
    nodes = f"node(s) {', '.join(str(i) for i in att.nodes)}" if att.nodes else ""
    return {
        "none": "–",
        "bias": f"{nodes}: + {att.magnitude:g} sd from {att.start:.0%} of the horizon",
        "replacement": f"{nodes}: with prob. {att.prob:g} replaced by U(±{att.magnitude:g} sd)",
        "message": f"every received message, prob. {att.prob:g}: estimate + {att.magnitude:g} sd",
        "dos": f"all links: Gilbert-Elliott p = {att.p:g}, q = {att.q:g}",
    }[att.kind]


rows = ["| scenario | plant | n | dt [s] | τ [steps] | horizon [steps] | network | N | attack | "
        "kind: parameters |", "|---|---|---|---|---|---|---|---|---|---|"]
for sc in SCENARIOS:
    rows.append(f"| `{sc.name}` | {md(sc.plant.name)} | {sc.plant.n} | {sc.plant.dt:g} | "
                f"{sc.time_constant:.3g} | {sc.horizon} | "
                f"{md(sc.network.name)} | {sc.network.N} | {md(sc.attack.name)} | "
                f"{sc.attack.kind}: {md(attack_parameters(sc.attack))} |")
display(Markdown("\n".join(rows)))

plants_used = list(dict.fromkeys(sc.plant.name for sc in SCENARIOS))
nets_used = list(dict.fromkeys(sc.network.name for sc in SCENARIOS))
atts_used = list(dict.fromkeys(sc.attack.name for sc in SCENARIOS))
display(Markdown("\n".join(
    ["| card | title | source |", "|---|---|---|"]
    + [f"| plant `{p}` | {md(CARDS['plant'][p].title)} | {md(CARDS['plant'][p].source)} |"
       for p in plants_used]
    + [f"| network `{n}` | {md(CARDS['network'][n].title)} | cards |" for n in nets_used]
    + [f"| attack `{a}` | {md(CARDS['attack'][a].title)} | cards |" for a in atts_used])))

# %% [markdown]
# ## The methods
#
# Generated from the registry (`secest.arena.estimators.METHODS`, filled when any arena module is
# imported): a new method is one `Method` subclass passed to `register`, and it appears here and in
# every table and figure below. The *reading* says how a method is applied where its paper's
# setting differs (`Method.reading`); *home* is the card of its paper's own example where the
# arena hosts it (and why not elsewhere); *requirements* are what it needs to run at all, and
# *theory* the conditions whose failure marks a cell (the texts are the methods' own).

# %%
rows = ["| method | kind | title | our reading on the shared scenarios | home | requirements | "
        "conditions of its theory |", "|---|---|---|---|---|---|---|"]
for name in method_names:
    m = METHODS[name]
    reqs = list(dict.fromkeys(text for sc in SCENARIOS for text, _ in m.requirements(sc)))
    conds = list(dict.fromkeys(text for sc in SCENARIOS for text, _ in m.conditions(sc)))
    home = f"`{m.home}`: {m.home_note}" if m.home else (m.home_note or "–")
    rows.append(f"| `{name}` | {m.kind} | {md(m.title)} | {md(m.reading or '–')} | {md(home)} | "
                f"{md('; '.join(reqs)) if reqs else '–'} | {md('; '.join(conds)) if conds else '–'} |")
display(Markdown("\n".join(rows)))

# %% [markdown]
# ## The matrix
#
# `secest.arena.matrix.run_matrix` runs `secest.arena.estimators.evaluate` once per scenario (one trial, every
# method, the oracle as the unit) and keeps each method's network-mean RMS error over time for the
# figures. What each method costs per scenario is machine-dependent: it goes to the run manifest
# `build/runs/arena.json` (not committed) and to `make bench`, never into this notebook.

# %%
with warnings.catch_warnings(record=True) as caught:  # the methods' own warnings, said once each
    warnings.simplefilter("always")
    MATRIX = matrix.run_matrix(SCENARIOS, method_names, short=SHORT)
said = sorted({f"{w.category.__name__}: {str(w.message).splitlines()[0]}" for w in caught})
print(f"{len(caught)} warnings raised by the methods, {len(said)} distinct" + (":" if said else ""))
for line in said:
    print("  " + line)
status_counts = {s: sum(c.status == s for c in MATRIX.cells.values()) for s in matrix.STATUSES}
print(f"{len(MATRIX.cells)} cells: " + ", ".join(f"{n} {s}" for s, n in status_counts.items()))

# %% [markdown]
# One table per plant, every method as printed (the tuned rows of the protocol are not yet run).
# Scores are unit-free (oracle = 1) with their 95 % intervals; rates in percent (– where the method
# has no detector, or the scenario no attacked sample); the last column lists the conditions of the
# method's theory that fail in that cell (scored all the same).

# %%
for table in report.plant_tables(MATRIX).values():  # secest.arena.report, as python -m secest.arena
    display(Markdown(table))

# %% [markdown]
# ## Heatmap of the whole matrix
#
# Every cell's steady-window score on a logarithmic colour scale (1 = the oracle; colours saturate
# at 1000), the number printed in the cell; a dot marks a cell outside the method's theory; hatched
# grey cells are N/A (the requirement is in the tables above), black cells diverged. Rows are
# grouped by plant, columns into baselines and the papers' methods.

# %%
TOL = results.Tolerance(
    rtol=max(METHODS[n].tolerance.rtol for n in method_names),
    atol=max(METHODS[n].tolerance.atol for n in method_names),
    reason="the loosest reproduction tolerance of the methods in the table ("
    + "; ".join(f"{n}: {METHODS[n].tolerance.reason}" for n in method_names
                if METHODS[n].tolerance != results.DETERMINISTIC)
    + "; every other method deterministic)")


def method_style(name: str) -> dict:
    """Baselines in black / greys with their own dashes, the papers' methods in colour, solid."""
    baselines = [n for n in method_names if METHODS[n].kind != "paper"]
    papers = [n for n in method_names if METHODS[n].kind == "paper"]
    if name == "oracle":
        return {"color": "black", "ls": (0, (4, 2)), "lw": 1.4, "zorder": 4}
    if name in baselines:
        colours = ["tab:gray", "tab:brown", "tab:olive", "tab:cyan", "tab:pink"]
        dashes = [(0, (1, 1.5)), (0, (6, 2, 1, 2)), (0, (3, 1, 1, 1, 1, 1)), (0, (8, 3))]
        i = baselines.index(name) - 1
        return {"color": colours[i % len(colours)], "ls": dashes[i % len(dashes)], "lw": 1.3}
    return {"color": f"C{papers.index(name) % 5}", "ls": "-", "lw": 1.3}


order = report.method_order(method_names)  # baselines, then the papers' methods
fig = report.heatmap(MATRIX, width=plotting.PAGE_WIDTH, title=(
    f"Arena: steady-window score, oracle = 1 ({runs_used} runs, seed {seed}, "
    f"attack magnitudes ×{attack_scale:g})"))
heatmap_png = plotting.save_figure(fig, FIG_DIR, "extra_matrix_heatmap", data=report.columns(MATRIX),
                                   tolerance=TOL)

# %% [markdown]
# ## Error over time, one figure per plant
#
# The network-mean RMS error $\big(\tfrac{1}{RN}\sum_{r,i}\lVert\hat x_{i,k}-x_k\rVert^2\big)^{1/2}$
# over the $R$ runs and $N$ nodes against time, one panel per attack, one curve per method
# (logarithmic axis), in the units of the state (the figures show what the unit-free scores
# summarise). The dotted vertical line is where the steady window starts (five time constants of
# the plant); shaded red are the steps at which the attack acts in at least one run (the sensor
# bias starts at 30 % of the horizon, the other attacks act throughout, intermittently).

# %%
def plain_log_ticks(ax: plt.Axes) -> None:
    """Tick labels of a log axis as plain numbers (0.5, 1, 2 rather than 5 x 10^-1)."""
    low, high = ax.get_ylim()
    if high / low > 1e4:  # many decades: powers of ten
        ax.yaxis.set_major_formatter(LogFormatterSciNotation())
        ax.yaxis.set_minor_formatter(NullFormatter())
        return
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    if high / low < 30:  # less than ~1.5 decades: label the minor ticks too, sparsely
        ax.yaxis.set_minor_formatter(FuncFormatter(
            lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "25" else ""))
    else:
        ax.yaxis.set_minor_formatter(NullFormatter())


def error_figure(plant: str) -> None:
    group = [sc for sc in SCENARIOS if sc.plant.name == plant]
    cols = 3 if len(group) > 2 else len(group)
    rows_ = -(-(len(group) + 1) // cols)
    fig, axes = plt.subplots(rows_, cols, figsize=(plotting.PAGE_WIDTH, 2.0 * rows_ + 0.4),
                             sharex=True, squeeze=False)
    data: dict[str, list] = {k: [] for k in ("scenario", "method", "k", "t", "rms", "attack_active")}
    for ax, sc in zip(axes.flat, group, strict=False):
        cur = MATRIX.curves[sc.name]
        t = cur.t
        ax.axvline(t[cur.settle], color="0.3", ls=(0, (1, 2)), lw=1.0)
        acting = np.flatnonzero(cur.active > 0)
        if acting.size:
            ax.axvspan(t[acting[0]], t[acting[-1]], color="tab:red", alpha=0.12, lw=0)
        for name in order:
            if name not in cur.rms:
                continue
            y = cur.rms[name]
            if np.all(np.isfinite(y)):
                ax.plot(t, y, label=name, **method_style(name))
            for k, (tk, yk) in enumerate(zip(t, y, strict=True)):
                data["scenario"].append(sc.name)
                data["method"].append(name)
                data["k"].append(k)
                data["t"].append(float(tk))
                data["rms"].append(float(yk))
                data["attack_active"].append(float(cur.active[k]))
        ax.set_yscale("log")
        plain_log_ticks(ax)
        missing = [n for n in order if n not in cur.rms]
        ax.set_title(f"{sc.attack.name}" + (f" (N/A: {', '.join(missing)})" if missing else ""),
                     fontsize=8)
        ax.set_xlim(t[0], t[-1])
    for ax in axes[:, 0]:
        ax.set_ylabel("RMS error [units of x]")
    for ax in axes[-1]:
        ax.set_xlabel("time t [s]")
    spare = axes.flat[len(group)]
    handles = [plt.Line2D([], [], label=n, **method_style(n)) for n in order]
    handles += [plt.Line2D([], [], color="0.3", ls=(0, (1, 2)), lw=1.0,
                           label="steady window starts"),
                Patch(color="tab:red", alpha=0.12, label="attack acts (some run)")]
    spare.legend(handles=handles, loc="center", fontsize=7, frameon=False, ncols=2)
    spare.axis("off")
    for ax in axes.flat[len(group) + 1:]:
        ax.axis("off")
    fig.suptitle(f"{plant}: network-mean RMS error over {group[0].runs} runs "
                 f"({group[0].network.name}, {group[0].network.N} nodes)", fontsize=9)
    fig.tight_layout()
    plotting.save_figure(fig, FIG_DIR, f"extra_error_{plant}", data=data,
                         tolerance={"rms": TOL})
    plt.show()


for plant in plants_used:
    error_figure(plant)

# %% [markdown]
# ## Robustness over the declared space
#
# The declared space (`notebooks/arena.toml`: the cards' seed and three others, crossed with the
# attack magnitudes scaled by 0.1, 1 and 10) has **not been swept for this design**: with every
# plant at its own horizon (twenty time constants: 410, 2860 and 1810 steps) and fifteen methods, a
# point costs several CPU-minutes, and the pre-registered protocol's validation and test seeds
# replace the seed axis (issue #28). The verdicts below are therefore the outcomes at this point.

# %% [markdown]
# ## Findings (claims)
#
# Each finding is a measurement with a rule on its interval, stated before this design's first
# run; none says which method should win, and each is reported **per plant** (the plant of a
# method's own paper example marked *home*). Only the cross of networks and attacks enters them.
# The thresholds are ours: **within a factor 2** of the oracle means the upper 95 % bound of the
# steady-window score is at most 2; a false-alarm rate is acceptable when its upper bound is at
# most 1 %; a detector *sees* an attack when the lower bound of its detection rate is at least 50 %.
#
# | id | what is measured, and the rule |
# |---|---|
# | X1 | consistency: no *distributed* method (every method but the oracle and the centralised `kf`, `chi2-kf`, which equal or bound the oracle by construction) scores below the oracle beyond its interval (smallest upper bound $\ge1$) |
# | X2 | without attack, every paper method stays within a factor 2 on every plant (listed per plant, home marked) |
# | X3 | premise of the attack columns: every attack card degrades, on every plant, the undefended baseline it reaches (`kf` under sensor attacks, `consensus-kf` under message and link attacks): lower bound of its score $>1$ and above its no-attack upper bound |
# | X4_&lt;attack&gt; | per attack: the methods within a factor 2 on every plant where the attack degrades its baseline (X3), among the methods the attack can reach (message and DoS: only methods whose nodes exchange messages); holds when a paper method is; `fails-premise` when the attack degrades its baseline on no plant |
# | X5 | applicability: every paper method runs (is not N/A) in every cell; the cells outside each method's theory are counted beside it |
# | X6 | every method with a detector keeps its false-alarm rate's upper bound at most 1 % in every cell where it runs |
# | X7 | every method with a detector sees every sensor attack on every plant where the attack degrades `kf`: lower bound of its detection rate $\ge50$ % |
# | X8 | no method diverges (growth rule or a non-finite estimate) in any cell |

# %%
FACTOR, FA_MAX, DET_MIN = 2.0, 0.01, 0.5
SECTION = "Findings (claims)"
cross = [sc for sc in SCENARIOS if sc.name == f"{sc.network.name}/{sc.attack.name}"]
cross_nets = list(dict.fromkeys(sc.network.name for sc in cross))
cross_atts = list(dict.fromkeys(sc.attack.name for sc in cross))
paper = [n for n in method_names if METHODS[n].kind == "paper"]
others = [n for n in method_names if n != "oracle"]
centralised = [n for n in others if not METHODS[n].exchanges and METHODS[n].name in ("kf", "chi2-kf")]


def cells_of(name: str, attack: str | None = None) -> list[tuple[str, object]]:
    return [(sc.name, MATRIX.cell(sc.name, name)) for sc in cross
            if attack is None or sc.attack.name == attack]


def cell(net: str, att: str, name: str):
    return MATRIX.cell(f"{net}/{att}", name)


def plant_label(net: str, name: str) -> str:
    return f"{net} (home)" if METHODS[name].home == net else net


def tolerance_of(names: list[str]) -> results.Tolerance:
    tols = [METHODS[n].tolerance for n in names] or [results.DETERMINISTIC]
    loose = max(tols, key=lambda t: (t.rtol, t.atol))
    return results.Tolerance(max(t.rtol for t in tols), max(t.atol for t in tols), loose.reason)


claims = {}
# X1: the oracle is a floor for every method that does not see the centralised data
distributed = [n for n in others if n not in ("kf", "chi2-kf")]
uppers = [(c.steady[2], s, n) for n in distributed for s, c in cells_of(n) if c.status == "ok"]
low_upper, low_where, low_method = min(uppers) if uppers else (1.0, "-", "-")
claims["X1"] = results.claim(
    paper="(ours) consistency of the arena's scores: no distributed method estimates better than "
    "the oracle (the centralised Kalman filter on clean data) beyond the uncertainty of its score",
    check="smallest upper 95 % bootstrap bound of a steady-window network score over every scored "
    "cell of the cross, every method except the oracle, kf and chi2-kf (centralised: kf equals the "
    "oracle without a sensor attack by construction); holds when >= 1",
    measured={"min_upper": low_upper, "cell": f"{low_where}, {low_method}", "cells": len(uppers)},
    threshold=1.0, holds=bool(low_upper >= 1.0), source="ours", key="min_upper",
    tolerance=tolerance_of(distributed), runs=runs_used, section=SECTION)

# X2: the price of security without attack, per plant
none_atts = [a for a in cross_atts if CARDS["attack"][a].kind == "none"]
x2 = {"per_plant": {}, "outside": [], "not_scored": {}}
for name in paper:
    for net in cross_nets:
        for a in none_atts:
            c = cell(net, a, name)
            label = plant_label(net, name)
            if c.status != "ok":
                x2["not_scored"][f"{name} on {label}"] = c.status + (f": {c.reason}" if c.reason else "")
                x2["outside"].append(name)
                continue
            x2["per_plant"].setdefault(label.split(" ")[0], {})[name + (" (home)" if "home" in label else "")] = c.steady[2]
            if c.steady[2] > FACTOR:
                x2["outside"].append(name)
x2["outside"] = sorted(set(x2["outside"]))
x2["n_outside"] = len(x2["outside"])
claims["X2"] = results.claim(
    paper="(ours) without attack, the papers' defences cost little accuracy: every paper method "
    "keeps its steady-window score within a factor 2 of the oracle on every plant",
    check="per plant and paper method, the upper 95 % bound of its steady-window network score on "
    "the attack-free scenario (home plants marked); a cell not scored (N/A, diverged, error) counts "
    "as outside; holds when no paper method is outside",
    measured=x2, threshold=FACTOR, holds=x2["n_outside"] == 0, source="ours", key="n_outside",
    tolerance=tolerance_of(paper), runs=runs_used, section=SECTION)

# X3: every attack card is felt by the undefended baseline it reaches, per plant
x3 = {"degrades": {}, "not_degraded": []}
for a in cross_atts:
    kind = CARDS["attack"][a].kind
    if kind == "none":
        continue
    base = "kf" if kind in ("bias", "replacement") else "consensus-kf"
    for net in cross_nets:
        attacked, clean = cell(net, a, base), cell(net, none_atts[0], base)
        felt = bool(attacked.status != "ok" or (
            attacked.steady[1] > 1.0 and clean.status == "ok" and attacked.steady[1] > clean.steady[2]))
        x3["degrades"][f"{a} on {net} ({base})"] = felt
        if not felt:
            x3["not_degraded"].append(f"{a} on {net}")
x3["n_not_degraded"] = len(x3["not_degraded"])
claims["X3"] = results.claim(
    paper="(ours) premise of the attack columns: every attack card measurably degrades, on every "
    "plant, the undefended baseline it reaches, so that each attack cell tests something",
    check="per attack and plant: the lower 95 % bound of the steady-window score of kf (sensor "
    "attacks) or consensus-kf (message and link attacks) under the attack exceeds 1 and its upper "
    "bound without attack (or the baseline is not scored: diverged); holds when every cell does",
    measured=x3, threshold=1.0, holds=x3["n_not_degraded"] == 0, source="ours",
    key="n_not_degraded", tolerance=tolerance_of(["kf", "consensus-kf"]), runs=runs_used,
    section=SECTION)

# X4_<attack>: who stays within a factor 2 where the attack bites
for a in cross_atts:
    kind = CARDS["attack"][a].kind
    if kind == "none":
        continue
    base = "kf" if kind in ("bias", "replacement") else "consensus-kf"
    bites = [net for net in cross_nets if x3["degrades"][f"{a} on {net} ({base})"]]
    reach = [n for n in others if kind in ("bias", "replacement") or METHODS[n].exchanges]
    x4 = {"plants": bites, "upper": {}, "within": [], "not_scored": []}
    for name in reach:
        cs = [cell(net, a, name) for net in bites]
        if not cs:
            continue
        if any(c.status != "ok" for c in cs):
            x4["not_scored"].append(name)
            continue
        x4["upper"][name] = max(c.steady[2] for c in cs)
        if x4["upper"][name] <= FACTOR:
            x4["within"].append(name)
    x4["paper_within"] = sum(n in paper for n in x4["within"])
    cid = "X4_" + re.sub(r"\W", "", a)
    claims[cid] = results.claim(
        paper=f"(ours) under the attack '{a}' ({CARDS['attack'][a].title}), at least one paper "
        "method keeps its steady-window score within a factor 2 of the oracle on every plant where "
        "the attack degrades the undefended baseline",
        check="per method the attack reaches (message and DoS: methods whose nodes exchange "
        "messages), the largest upper 95 % bound of its steady-window score over the plants where "
        "X3 finds the attack felt; 'within' lists those <= 2, 'not_scored' those N/A, diverged or "
        "failing on one of them; holds when a paper method is within; fails-premise when the "
        "attack is felt on no plant",
        measured=x4, threshold=FACTOR, holds=bool(x4["paper_within"] >= 1), source="ours",
        premise=("(X3) the attack degrades the undefended baseline on at least one plant",
                 bool(bites)),
        key="paper_within", tolerance=tolerance_of(others), runs=runs_used, section=SECTION)

# X5: applicability, the same rule for every method
x5 = {"n/a": {}, "outside_theory": {}}
for name in paper:
    cs = cells_of(name)
    x5["n/a"][name] = {s: c.reason for s, c in cs if c.status == "n/a"}
    x5["outside_theory"][name] = sum(bool(c.outside) for _, c in cs)
x5["cells"] = len(cross)
x5["n_na"] = sum(len(v) for v in x5["n/a"].values())
claims["X5"] = results.claim(
    paper="(ours) applicability: every paper method runs in every cell of the cross (N/A only "
    "where a method cannot run at all; cells outside its theory are scored and marked)",
    check="per paper method, the cells where a requirement fails (Method.requirements, N/A) and "
    "the number of scored cells outside its theory (Method.conditions); holds when no paper "
    "method is N/A anywhere",
    measured=x5, threshold=0, holds=x5["n_na"] == 0, source="ours", key="n_na", section=SECTION)

# X6, X7: detectors
detectors = [n for n in others if any(c.false_alarm is not None for _, c in cells_of(n))]
x6 = {"upper": {}, "cell": {}}
for name in detectors:
    fa = [(c.false_alarm[2], s) for s, c in cells_of(name) if c.false_alarm is not None]
    x6["upper"][name], x6["cell"][name] = max(fa)
x6["worst_upper"] = max(x6["upper"].values()) if x6["upper"] else 0.0
claims["X6"] = results.claim(
    paper="(ours) the detectors rarely raise false alarms: every method with a detector keeps its "
    "false-alarm rate below 1 % in every scenario where it runs",
    check="per method with alarms, the largest upper 95 % bound (union of Wilson and a bootstrap "
    "over runs) of its false-alarm rate on the steady window over the cells of the cross; holds "
    "when every one is <= 1 %",
    measured=x6, threshold=FA_MAX, holds=bool(x6["worst_upper"] <= FA_MAX), source="ours",
    key="worst_upper", tolerance=tolerance_of(detectors), runs=runs_used, section=SECTION)

sensor_cells = [(a, net) for a in cross_atts if CARDS["attack"][a].kind in ("bias", "replacement")
                for net in cross_nets if x3["degrades"][f"{a} on {net} (kf)"]]
x7 = {"lower": {}, "cell": {}}
for name in detectors:
    det = [(cell(net, a, name).detection[1], f"{net}/{a}") for a, net in sensor_cells
           if cell(net, a, name).status == "ok" and cell(net, a, name).detection is not None]
    if det:
        x7["lower"][name], x7["cell"][name] = min(det)
x7["worst_lower"] = min(x7["lower"].values()) if x7["lower"] else 0.0
claims["X7"] = results.claim(
    paper="(ours) every method with a detector sees the sensor attacks: it flags at least half of "
    "the attacked samples under the bias and the replacement on every plant where they degrade kf",
    check="per method with alarms, the smallest lower 95 % bound of its detection rate over the "
    "sensor-attack cells where X3 finds the attack felt; holds when every one is >= 50 %",
    measured=x7, threshold=DET_MIN, holds=bool(x7["lower"]) and x7["worst_lower"] >= DET_MIN,
    source="ours", key="worst_lower", tolerance=tolerance_of(detectors), runs=runs_used,
    premise=("(X3) a sensor attack degrades kf on at least one plant", bool(sensor_cells)),
    section=SECTION)

# X8: divergence by growth
diverged = {f"{s}, {n}": c.reason for n in others for s, c in cells_of(n) if c.status == "diverged"}
claims["X8"] = results.claim(
    paper="(ours) no method diverges on the shared scenarios",
    check="number of cells of the cross that are diverged: an estimate not finite, or the mean "
    "squared normalised error of the last quarter of the steady window above 4 times that of its "
    "second quarter; holds when 0",
    measured={"diverged": len(diverged), "cells": diverged}, threshold=0,
    holds=not diverged, source="ours", key="diverged", runs=runs_used, section=SECTION)

written = json.loads(results.write_claims(results_path, claims).read_text())
for cid, c in written.items():
    print(f"{cid}: {c['verdict']} at this point (no sweep of this design yet)")

# %% [markdown]
# The measured values behind each finding:


# %%
def short(value: object) -> str:
    if isinstance(value, float):
        return matrix._sig(value)
    if isinstance(value, dict):
        return "; ".join(f"{k}: {short(v)}" for k, v in value.items()) or "–"
    if isinstance(value, list):
        return ", ".join(short(v) for v in value) or "none"
    return str(value)


display(Markdown("\n".join(
    ["| id | outcome | measured |", "|---|---|---|"]
    + [f"| {cid} | {c['verdict']} | {md(short(c['measured']))} |" for cid, c in written.items()])))

# %% [markdown]
# ## Deviations and limitations
#
# Nothing in this notebook is a paper's claim: the scenarios, the baselines, the scores and the
# rules of the findings are ours. Each paper method runs here on plants, networks and attacks its
# paper did not consider, read as follows: our reading of each method, as recorded in
# `Method.reading` (where it fixes a value or a design choice the paper does not state, the choice
# is ours; the details are in `secest/methods/<key>.py`):

# %%
display(Markdown("\n".join(
    ["| method | our reading on the shared scenarios |", "|---|---|"]
    + [f"| `{n}` | {md(METHODS[n].reading or '–')} |" for n in method_names])))

# %% [markdown]
# | # | item | here | why |
# |---|---|---|---|
# | A1 | scenarios | three plants (ding2020's target, lee2020's three-inertia system, Johansson's quadruple tank) on stand-in networks, four attack cards of our strength | no paper fixes a common ground; only two of the five papers' examples are hostable (home cards): guo2023's is time-varying with an unknown input, li2025's singularly perturbed and scheduled, ma2021's nonlinear |
# | A2 | reference | the centralised Kalman filter on clean data (oracle), its error covariance the unit of every score | the best any method can do with the same information; whitening by it makes the score unit-free and the same on every plant |
# | A3 | windows | transient $[0,5\tau)$, steady $[5\tau,K]$, $K=20\tau$, $\tau$ the slower of the oracle's error decay and the plant's slowest decaying mode | each plant's own time scale (a correction of the protocol's first wording, which named the oracle's decay only, made before any test-seed result: `protocol.toml`) |
# | A4 | noise | Gaussian clipped at 3 sd | bounded noise keeps ma2021's ellipsoidal assumption true while the covariance stays within 3 % of the nominal one |
# | A5 | detectors | `alarms` as each method defines them; guo2023's chi-square test of the attack estimate and `chi2-kf` are ours | the rates compare what each method flags, not a common test |
# | A6 | rules of the findings | factor 2 on the steady score, 1 % false alarms, 50 % detection, all on 95 % bounds | ours, stated before this design's run; the tables give every number for other rules |
# | A7 | intervals | bootstrap over runs (scores); union of Wilson and a bootstrap over runs (rates) | runs are independent, (run, step, node) samples are not |
# | A8 | methods without links | the oracle, `kf`, `chi2-kf` and `local-kf` exchange no messages | on the message and DoS columns they are references, not competitors (X4 leaves them out there) |
# | A9 | what a method is told | guo2023 is told which sensor the attack card names (its $H^i$: the paper assumes the attack channels known); li2025 the replacement card's probability and magnitude ($\check\psi$, $\xi^*$: its paper assumes them known); the others nothing about the attack | each paper's own assumption, kept; an advantage under the sensor attacks that the tables do not separate from the method itself |
# | A10 | settings | every method as its paper printed it (ding2020's $\kappa$ and threshold, lee2020's $\kappa,\gamma$, li2025's weights, ma2021's $p$), the baselines at their textbook defaults; ma2021's recursion (30) holds its gains once $P_k$ settles (relative change $\le10^{-6}$ on ten steps) | the tuned rows of the pre-registered protocol are not yet run (issue #28) |
# | A11 | falsified messages | a shift of 20 oracle steady-state sd of the state estimate a node sends, mapped into each method's message by its own encoding | one attack for every method, in physical units (the first design added a bounded injection in each method's own message units, which made the columns incomparable) |

# %%
per_method: dict[str, float] = {}
for (_, name), seconds in MATRIX.seconds.items():
    per_method[name] = per_method.get(name, 0.0) + seconds
manifest_path = run.finish(extra={"seconds_per_method": per_method,
                                  "seconds_per_cell": {f"{s}|{n}": t for (s, n), t in MATRIX.seconds.items()}})
print("run manifest:", manifest_path.relative_to(results.repo_root()))

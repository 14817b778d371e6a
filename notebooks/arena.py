# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # arena — every estimator against every attack, printed and tuned, on the test seeds
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
# `diffusion-kf`; `kcf`, Olfati-Saber's Kalman consensus filter), one with several consensus rounds
# per step (`consensus-kf`), and a Byzantine-resilient one (`wmsr-kf`, trimmed consensus).
#
# **One tuning rule, registered before the test.** Every method is reported twice: *printed* (its
# paper's example values, or a baseline's textbook default) and *tuned* (its free constants chosen
# per plant by the one rule of `secest/arena/protocol.toml` on the validation seeds 101–104: the
# lowest attack-free steady score among the points that do not diverge and, for a method with a
# detector, keep the upper 95 % bound of their false alarms at most 1 %). The rule, the search sets
# and the seed split were committed before any validation or test run, the tuned constants
# (`figures/arena/tuned.json`) before the test seeds 301–308 ran (`figures/arena/test.json`
# records both commits; the test stage refuses to run on a tuned file git has not committed
# unmodified, or made under another `protocol.toml`). Three amendments of the divergence,
# applicability and tuning rules came **after** a test stage had been looked at; each time the
# validation and the test stage ran again in full (deviations A13, A15 and A16 below, with the
# earlier stages' numbers in ERRATA.md). The last one also retired the test seeds 201–208, seen
# under two or three versions of the rules: the rules in force met the seeds 301–308 once, in this
# stage.
# This notebook runs no matrix: it reads those two committed files and regenerates
# every table, figure and finding from them (`make robustness NB=arena`, then `make arena-test`,
# then `make figures NB=arena`).
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
# **What it finds** is written from the data in the section *What the test seeds show* below, per
# plant, each paper's home plant marked. Everything here is ours: no paper makes these
# comparisons, and each method is *read* on scenarios its paper did not consider (how, in the
# section on limitations). The findings are measurements with rules stated before the run, not
# rankings: a method that loses here may win on its own paper's setting, which its notebook
# reproduces.

# %% tags=["parameters"]
mode = "paper"  # "paper": the protocol's test stage; "fast": also a smoke test's files, a 10-step live cell (tests) (ours)
tuned_path = "figures/arena/tuned.json"  # the committed tuning result, from make robustness for the arena (ours)
test_path = "figures/arena/test.json"  # the test stage's result on the test seeds (make arena-test) (ours)
figures = True  # False: no figure or data file is made (ours)
fig_dir = "figures/arena"
results_path = "figures/arena/claims.json"

# %%
import hashlib
import json
import re
import warnings
from dataclasses import replace

import numpy as np
from IPython.display import Markdown, display

from secest.arena import estimators, matrix, protocol, report, scenarios
from secest.arena.estimators import METHODS, Score
from secest.core.validation import ValidationError
from secest.repro import plotting, results, spaces

print(results.environment_summary())
# the methods' warnings name what went wrong, not where the repository is checked out
warnings.formatwarning = lambda message, category, *_, **__: f"{category.__name__}: {message}\n"

run = results.Run("arena", globals())
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)


def read(label: str, path: str) -> tuple[dict, str]:
    """A committed JSON file and its SHA-256."""
    file = results.resolve(path)
    if not file.is_file():
        raise ValidationError(f"{label}: {path} does not exist (make robustness NB=arena, commit "
                              "figures/arena/tuned.json, then make arena-test)")
    return json.loads(file.read_text()), hashlib.sha256(file.read_bytes()).hexdigest()


TUNED, tuned_sha = read("tuned_path", tuned_path)
TEST, _ = read("test_path", test_path)
protocol_sha = hashlib.sha256((results.repo_root() / TEST["protocol"]["file"]).read_bytes()).hexdigest()
if TEST["tuned"]["sha256"] != tuned_sha:
    raise ValidationError(f"test_path: {test_path} ran on another tuned file (SHA-256 "
                          f"{TEST['tuned']['sha256'][:12]}), not on {tuned_path} ({tuned_sha[:12]})")
if TEST["protocol"]["sha256"] != protocol_sha:
    raise ValidationError(f"test_path: {test_path} ran under another protocol.toml than this one")
if mode == "paper" and (TEST["short"] or TUNED["protocol"]["short"]):
    raise ValidationError(f"test_path: {test_path} is a smoke test's (short); paper mode reads the "
                          "protocol's test stage")
PLANTS = list(TEST["plants"])  # from the data: a plant added to the tuning appears here
ATTACKS = list(TEST["attacks"])
KINDS = ("printed", "tuned")
CARDS = scenarios.cards()
if not [a for a in ATTACKS if CARDS["attack"][a].kind == "none"]:
    raise ValidationError(f"test_path: {test_path} has no attack-free card (attacks {ATTACKS}): "
                          "the findings compare every attack with it")
SCENARIOS = [scenarios.scenario(net, att, horizon=TEST["plants"][net]["horizon"],
                                runs=TEST["runs_per_seed"], seed=TEST["seeds"][0])
             for net in PLANTS for att in ATTACKS]
HOME_SCENARIOS = [scenarios.scenario(net, TEST["plants"][net]["homes"][name]["attack"],
                                     horizon=TEST["plants"][net]["horizon"],
                                     runs=TEST["runs_per_seed"], seed=TEST["seeds"][0], name=name)
                  for net in PLANTS for name in TEST["plants"][net].get("homes", {})]
method_names = list(dict.fromkeys(r["method"] for rec in TEST["plants"].values()
                                  for rows in rec["cells"].values() for r in rows))
unknown = [m for m in method_names if m not in METHODS]
if unknown:
    raise ValidationError(f"test_path: methods {unknown} are not registered")
RUNS = len(TEST["seeds"]) * TEST["runs_per_seed"]
REGISTERED = protocol.load()["seeds"]
print(f"{len(PLANTS)} plants x {len(ATTACKS)} attacks x {len(method_names)} methods (printed and "
      f"tuned), test seeds {TEST['seeds']}, {TEST['runs_per_seed']} runs each ({RUNS} pooled)")
if TEST["seeds"] != REGISTERED["test"] or TEST["runs_per_seed"] != REGISTERED["runs_per_seed"]:
    print(f"DEVIATION from protocol.toml: it registers test seeds {REGISTERED['test']} with "
          f"{REGISTERED['runs_per_seed']} runs each; this test stage ran {TEST['seeds']} with "
          f"{TEST['runs_per_seed']} (ERRATA.md, arena)")
HOMES = {name: net for net in PLANTS for name in TEST["plants"][net].get("homes", {})}
print(f"home grounds on the test seeds: {HOMES or 'none'}")

# %% [markdown]
# ## The order: protocol, tuning, test
#
# The test stage (`secest.arena.testseeds`) refused to run unless the tuned constants were committed
# unmodified, and recorded which commits it ran on; the protocol's rule and search sets are older
# still. From `test.json`:

# %%
order = [
    ("the protocol (rule, search sets, seed split)", TEST["protocol"]["file"],
     TEST["protocol"]["commit"], TEST["protocol"]["sha256"]),
    ("the tuned constants (validation seeds " + ", ".join(map(str, TUNED["protocol"]["seeds"])) + ")",
     TEST["tuned"]["file"], TEST["tuned"]["commit"], TEST["tuned"]["sha256"]),
]
display(Markdown("\n".join(
    ["| what | file | commit | SHA-256 |", "|---|---|---|---|"]
    + [f"| {w} | `{f}` | `{(c or 'not recorded')[:12]}` | `{h[:16]}…` |" for w, f, c, h in order]
    + [f"| the test stage's result (test seeds {', '.join(map(str, TEST['seeds']))}) | "
       f"`{test_path}` | this file's commit | – |"])))

# %% [markdown]
# ## How to read the arena
#
# **One trial per scenario and test seed.** `secest.arena.scenarios.simulate` draws the runs of a
# scenario once per seed — the truth $x_k$, every sensor's noise, the attack, the channel — and every
# method, printed and tuned, estimates from that same draw. Differences between two methods in a
# scenario are therefore differences between the methods, not between draws (paired comparison).
# Changing the attack leaves the truth and the noises unchanged (common random numbers across an
# attack column of one plant). The runs of the eight test seeds are pooled: $\Sigma_o$ below, the
# bootstrap and the growth rule are computed over all of them (`secest.arena.testseeds.pool`).
#
# **A unit-free score.** With $e_{r,k,i}=\hat x_{i,k}-x_k$ the error of node $i$ at step $k$ of run
# $r$ and $\Sigma_o$ the oracle's error covariance pooled over the runs (of every test seed) and the window, the
# squared error $q_{r,k,i}=e^\top\Sigma_o^{-1}e/n$ does not change under any change of state
# coordinates, so position and acceleration, angles and rates, centimetres and volts weigh the
# same; the oracle's mean $q$ is exactly 1. A node's score is $\sqrt{\text{mean}_{r,k}\,q}$, the
# network score the mean over nodes (the worst node beside it), with a 95 % percentile
# bootstrap over the pooled runs (2000 resamples, seed 0).
#
# **Windows from each plant's own time scale.** $\tau$ is the slower of the oracle's error decay,
# $-1/\ln\rho((I-KC)A)$ steps, and the plant's slowest decaying open-loop mode (what a node that
# does not see a mode waits for; `secest.arena.scenarios.steady_state`). The transient window is
# $[0,5\tau)$, the steady window $[5\tau,K]$, and the horizon is $K=20\tau$ (rounded up to ten
# steps): each plant runs as long as it needs. Findings cite the steady window.
#
# **Divergence by growth, or by escape.** For each node $i$, with $m_i$ the mean $q$ over the runs
# on the second and on the last quarter of the steady window, the growth factor is
# $g_i=m_i^{\text{late}}/m_i^{\text{mid}}$ and the growth exponent $p_i=\ln g_i/\ln(\bar k_{\text{late}}/
# \bar k_{\text{mid}})$, $\bar k$ the mean step of each quarter: a mean squared error growing as $k^p$
# gives $p$ (to 1 % for $0<p\le 2$, exactly for $p=1$) on any horizon. Each $p_i$ has an
# interval over the runs, the $N$ of them holding together at 95 % (delta method for the log of a
# ratio of means, Student's $t$ with $R-1$ degrees of freedom at $1-0.025/N$: a few runs give a wide
# interval, and a network's $N$ tests together keep a 5 % error. $N$ is the plant's, the same for
# every method on it; a centralised filter's $N$ identical columns get the same, wider, quantile,
# which makes the rule more lenient for it than one test would be: no scored `kf` or `chi2-kf` row
# changes with $N=1$, a third review found). A cell is `diverged` when the lower bound
# of some node's $p_i$ exceeds $0.05$ (Amendment 3 of the protocol: a random walk, $p=1$, that
# carries a twentieth of a node's mean squared error at mid-window reaches it), when an estimate is
# not finite, or when it *escapes*: its steady-window RMS error over the pooled runs exceeds $10^4$
# times the oracle's (Amendment 2 judged escape per run, so its power grew with the run count;
# Amendment 3 judges the pooled runs). Before Amendment 3 the rule was a limit of 4, then 2, on the
# network's factor: it passed an error growing as $k$ (factor 1.71 on this window), hid a node
# that grows behind the network mean, and was judged per validation seed in the tuning but on the
# pooled runs in the test, so that one point could be diverged in one and bounded in the other. The
# tuning now pools its seeds by the test stage's own function. A diverged row shows the growth
# factor (of the node whose lower bound is the largest) with its interval and the reason, never a
# score (to 4 significant digits, above $10^6$ written `>1e6`: amplified round-off differs between
# machines). A scored row is *bounded* when every node's upper bound of $p$ is
# at most $0.05$; otherwise (some node's interval contains the limit: its runs neither show nor
# exclude the growth) it is marked ‡ *growth undecided* (Amendment 4; before it, only a row whose
# factor alone was above the limit). What 320 runs resolve is each row's interval, not the limit:
# `local-kf`'s two nodes on the three-inertia plant that do not see its rigid-body mode (a random
# walk) grow as $k^{0.082}$ on this window (their exact error covariance, a Riccati recursion: a
# test): closer to the limit than 320 runs resolve for those slow nodes (their interval's
# half-width was about $0.1$ in the third stage, against about $0.03$ for a typical row there; the
# census below gives this stage's). A growth slower than $k^{0.05}$ (e.g. logarithmic) is not seen
# by this window, a declared limit.
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
# (`Method.requirements`), the same rule for every method. A stability condition is a condition of
# the theory, not a requirement: `kcf` with $\epsilon\,d_{\max}\ge1$ runs, marked (the first test
# stage had it N/A on target20).

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
# same on every plant and for every method; the table shows them, and each plant's time constant,
# horizon and first steady step as the test stage ran them (`test.json`). The *data-free score* is
# the steady-window score of the estimate that uses no data at all ($\hat x_k=0$, the prior mean,
# whose error covariance $P_{k+1}=AP_kA^\top+Q$ from $P_0=\sigma_0^2I$ the code computes exactly:
# `secest.arena.estimators.data_free_moment`): the scale of the plant's scores; a method near it
# has learnt little from its data. It grows with the horizon where the plant has modes that do not
# decay (the target's), so it is a scale, not a rule.


# %%
def md(text: object) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def attack_parameters(att: scenarios.Attack) -> str:
    """The parameters an attack card sets, in words."""
    nodes = f"node(s) {', '.join(str(i) for i in att.nodes)}" if att.nodes else ""
    return {
        "none": "–",
        "bias": f"{nodes}: + {att.magnitude:g} sd " + (
            "at steps " + ", ".join("–".join(map(str, w)) + ("" if len(w) > 1 else " on")
                                    for w in att.windows) if att.windows
            else f"from {att.start:.0%} of the horizon") + (
            f"; links: Gilbert-Elliott p = {att.p:g}, q = {att.q:g}" if att.lossy else ""),
        "replacement": f"{nodes}: with prob. {att.prob:g} replaced by U(±{att.magnitude:g} sd)",
        "message": f"every received message, prob. {att.prob:g}: estimate + {att.magnitude:g} sd",
        "dos": f"all links: Gilbert-Elliott p = {att.p:g}, q = {att.q:g}",
    }[att.kind]


rows = ["| scenario | plant | n | dt [s] | τ [steps] | horizon [steps] | steady from [step] | "
        "data-free score | network | N | attack | kind: parameters |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for sc in SCENARIOS + HOME_SCENARIOS:
    rows.append(f"| `{sc.name}` | {md(sc.plant.name)} | {sc.plant.n} | {sc.plant.dt:g} | "
                f"{TEST['plants'][sc.network.name]['tau']:.3g} | {sc.horizon} | "
                f"{TEST['plants'][sc.network.name]['settle']} | "
                f"{matrix._sig(TEST['plants'][sc.network.name]['data_free'])} | "
                f"{md(sc.network.name)} | {sc.network.N} | {md(sc.attack.name)} | "
                f"{sc.attack.kind}: {md(attack_parameters(sc.attack))} |")
display(Markdown("\n".join(rows)))

plants_used = list(dict.fromkeys(sc.plant.name for sc in SCENARIOS + HOME_SCENARIOS))
nets_used = list(dict.fromkeys(sc.network.name for sc in SCENARIOS + HOME_SCENARIOS))
atts_used = list(dict.fromkeys(sc.attack.name for sc in SCENARIOS + HOME_SCENARIOS))
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
# arena hosts it (and why not elsewhere); *told* what it is given about the attack from the card
# (its paper's assumption: `Method.told`); *requirements* are what it needs to run at all, and
# *theory* the conditions whose failure marks a cell (the texts are the methods' own; every
# baseline declares its attack model too, so the marks are one rule for all). The readings
# describe each method at its printed constants; the tuned rows change only the constants of the
# tuning table below.

# %%
rows = ["| method | kind | title | our reading on the shared scenarios | told about the attack | home | "
        "requirements | conditions of its theory |", "|---|---|---|---|---|---|---|---|"]
for name in method_names:
    m = METHODS[name]
    reqs = list(dict.fromkeys(text for sc in SCENARIOS + HOME_SCENARIOS for text, _ in m.requirements(sc)))
    conds = list(dict.fromkeys(text for sc in SCENARIOS + HOME_SCENARIOS for text, _ in m.conditions(sc)))
    home = f"`{m.home}`: {m.home_note}" if m.home else (m.home_note or "–")
    told = list(dict.fromkeys(f"{sc.attack.name}: {t}" for sc in SCENARIOS + HOME_SCENARIOS
                              if (t := m.told(sc))))
    rows.append(f"| `{name}` | {m.kind} | {md(m.title)} | {md(m.reading or '–')} | "
                f"{md('; '.join(told)) if told else 'nothing'} | {md(home)} | "
                f"{md('; '.join(reqs)) if reqs else '–'} | {md('; '.join(conds)) if conds else '–'} |")
display(Markdown("\n".join(rows)))


# %% [markdown]
# ## The tuned constants and the rule that chose them
#
# Per plant, each method's printed point and the point the registered rule chose on the validation
# seeds (`tuned.json`): the constants, the rule's words, how many points of its search set were
# admissible, and *no admissible point* where every point diverged or exceeded the false-alarm cap
# (then the point of lowest false-alarm bound is reported, marked). A method whose tuned point is
# its printed one runs once and gives both rows.


# %%
def constants_text(constants: dict | None) -> str:
    if not constants:
        return "–"
    return ", ".join(f"{k} = {matrix._sig(v) if isinstance(v, float) else v}" for k, v in constants.items())


def printed_constants(net: str, name: str) -> dict | None:
    rows = [r for r in TEST["plants"][net]["cells"][ATTACKS[0]] if r["method"] == name]
    return next((r["constants"] for r in rows if r["row"] == "printed"), None)


for net in PLANTS:
    lines = [f"**Plant `{TEST['plants'][net]['plant']}` on `{net}`**", "",
             "| method | printed | tuned | rule | admissible points | mark |", "|---|---|---|---|---|---|"]
    for name, c in TUNED["tuned"][net].items():
        home = " (home)" if METHODS[name].home == net else ""
        n_points = len(TUNED["points"][net][name]) if "points" in TUNED else "–"
        lines.append(f"| `{name}`{home} | {md(constants_text(printed_constants(net, name)))} | "
                     f"{md(constants_text(c['constants']))}{' (= printed)' if c['point'] == 0 else ''} | "
                     f"{md(c['rule'])} | {len(c['admissible'])} of {n_points} | "
                     f"{'**' + c['mark'] + '**' if c['mark'] else ''} |")
    display(Markdown("\n".join(lines)))

# %% [markdown]
# ## The results on the test seeds, per plant
#
# One table per plant (its heading names the methods whose paper's example it is: *home*), one row
# per method and row kind under each attack: the steady-window network score and the worst node,
# the transient score (unit-free, oracle = 1, 95 % bootstrap intervals over the pooled runs), the
# detection and false-alarm rates (%, union of Wilson and a bootstrap over runs; – where the method
# has no detector, or the scenario no attacked sample), and the conditions of the method's theory
# that fail there (scored all the same). `diverged` rows give the growth factor, never a score; ‡
# marks a scored row whose growth is undecided (some node's interval of the growth exponent
# contains the limit).


# %%
def growth_text(row: dict) -> str:
    """A row's growth factor and, where stored (every row since Amendment 4), its 95 % interval."""
    def one(g: float | str | None) -> str:
        return str(g) if isinstance(g, str) else ("–" if g is None else matrix._sig(g, 3))

    interval = row.get("growth_interval")
    return one(row["growth"]) + (f" [{one(interval[0])}, {one(interval[1])}]" if interval else "")


def as_score(row: dict) -> Score:
    """A row of test.json as the arena's Score (tables, heatmap)."""
    def triple(key: str):
        return None if row[key] is None else tuple(row[key])

    reason = row["reason"]
    if row["status"] == "diverged" and row["growth"] is not None:
        reason = f"{reason} (growth {growth_text(row)})"
    growth = row["growth"] if isinstance(row["growth"], float) else None
    return Score(row["status"], reason, tuple(row["outside"]), triple("steady"), triple("worst"),
                 triple("transient"), growth, row["growth_undecided"], triple("detection"),
                 triple("false_alarm"))


CELLS = {kind: {} for kind in KINDS}
for net in PLANTS:
    for att, rows in TEST["plants"][net]["cells"].items():
        for r in rows:
            for kind in KINDS:
                if r["row"] == kind or r["row"] == "reference":
                    CELLS[kind][(net, att, r["method"])] = as_score(r)
            if r["row"] == "reference":
                CELLS.setdefault("reference", {})[(net, att, r["method"])] = as_score(r)


def row_words(s: Score) -> list[str]:
    t = matrix.cell_text(s)
    if s.status == "ok":
        mark = " ‡" if s.growth_undecided else ""
        return [t["steady"] + mark, t["worst"], t["transient"], t["detection"], t["false_alarm"]]
    return [f"**{md(t['steady'])}**", "", "", "", ""]


def plant_table(net: str) -> str:
    rec = TEST["plants"][net]
    home = ", ".join(f"`{m}`" for m in rec["home"])
    lines = [f"**Plant `{rec['plant']}` on `{net}`**" + (f" — home of {home}" if home else ""), "",
             "| attack | method | row | steady [95 % CI] | worst node | transient | detection | "
             "false alarm | outside its theory |", "|---|---|---|---|---|---|---|---|---|"]
    labelled = [(att, rows) for att, rows in rec["cells"].items()]
    labelled += [(f"home ground `{name}`", h["rows"]) for name, h in rec.get("homes", {}).items()]
    for att, rows in labelled:
        for r in rows:
            kind = r["row"] + (" (= tuned, one run)" if r["shared"] and r["row"] == "printed" else "")
            lines.append(f"| {att} | `{r['method']}` | {kind} | "
                         + " | ".join(row_words(as_score(r))) + f" | {md('; '.join(r['outside']))} |")
    return "\n".join(lines)


for net in PLANTS:
    display(Markdown(plant_table(net)))

# %% [markdown]
# **What the growth rule decided.** Per plant, over every row of the test stage (cross and home
# grounds, printed and tuned, the reference among them): how many rows the rule rules diverged by
# growth, how many it finds bounded (every node's upper bound of $p$ at most 0.05) and how many it
# leaves undecided (‡), with the median half-width of the growth exponent's interval of the scored
# rows (the node the rule reads): what the pooled runs resolve on that plant's window. Where that
# half-width is above the limit, the runs can show hardly any row bounded and ‡ says only *not
# resolved*, not *suspected growth*: the oracle itself carries it there. The mark is the same
# function for every row; with Bonferroni over the plant's $N$ nodes it is harsher for a centralised
# filter, whose $N$ identical columns widen its interval as $N$ distinct nodes would.


# %%
def exponent(factor: float, rec: dict) -> float:
    """A growth factor on a plant's steady window as the exponent p (protocol.toml [divergence])."""
    return estimators.growth_exponent(factor, rec["settle"], rec["horizon"] + 1 - rec["settle"])


def growth_census(net: str) -> dict:
    rec = TEST["plants"][net]
    rows = [r for rs in rec["cells"].values() for r in rs]
    rows += [r for h in rec.get("homes", {}).values() for r in h["rows"]]
    scored = [r for r in rows if r["status"] == "ok"]
    widths = [(exponent(r["growth_interval"][1], rec) - exponent(r["growth_interval"][0], rec)) / 2
              for r in scored]
    reference = {r["status"] + (" ‡" if r["growth_undecided"] else "") for r in rows
                 if r["row"] == "reference"}
    return {"rows": len(rows),
            "diverged by growth": sum(r["reason"].startswith("its error grows") for r in rows),
            "bounded": sum(not r["growth_undecided"] for r in scored),
            "undecided ‡": sum(r["growth_undecided"] for r in scored),
            "half-width of p": float(np.median(widths)), "oracle": ", ".join(sorted(reference))}


census = {net: growth_census(net) for net in PLANTS}
keys = list(next(iter(census.values())))
display(Markdown("\n".join(
    ["| plant | " + " | ".join(keys) + " |", "|---" * (len(keys) + 1) + "|"]
    + [f"| `{net}` | " + " | ".join(f"{v:.2f}" if isinstance(v, float) else str(v)
                                    for v in c.values()) + " |" for net, c in census.items()])))

# %% [markdown]
# **Where the home grounds' attacks act.** The papers' own attacks act early in their examples; the
# arena's windows come from the plant's time scale, so an attack may act only in the transient
# window, whose score is the *transient* column above (the steady column then measures the channel
# and the aftermath). From one run of each home card:


# %%
def attacked_steps(sc: scenarios.Scenario) -> np.ndarray:
    """The steps at which any sensor of ``sc`` is attacked, from one simulated run."""
    return np.flatnonzero(scenarios.simulate(replace(sc, runs=1)).attacked[0].any(axis=-1))


def ranges(hit: np.ndarray) -> str:
    """Sorted steps as ranges: ``50–55, 90–95``."""
    if not hit.size:
        return "none"
    breaks = np.flatnonzero(np.diff(hit) > 1)
    starts, ends = np.r_[hit[0], hit[breaks + 1]], np.r_[hit[breaks], hit[-1]]
    return ", ".join(f"{a}–{b}" if b > a else f"{a}" for a, b in zip(starts, ends, strict=True))


home_lines = ["| home ground | plant | attacked steps | transient window | the attack is scored in |",
              "|---|---|---|---|---|"]
for sc in HOME_SCENARIOS:
    settle = TEST["plants"][sc.network.name]["settle"]
    hit = attacked_steps(sc)
    where = ("no step" if not hit.size else "the transient column" if hit.max() < settle
             else "the steady column" if hit.min() >= settle else "both columns")
    home_lines.append(f"| `{sc.name}` | `{sc.network.name}` | {ranges(hit)} | [0, {settle}) | "
                      f"{where} |")
display(Markdown("\n".join(home_lines)))

# %% [markdown]
# ## Heatmaps, one per row kind
#
# Every cell's steady-window score on a logarithmic colour scale (1 = the oracle; colours saturate
# at 1000), the number printed in the cell; a dot marks a cell outside the method's theory; hatched
# grey cells are N/A (the requirement is in the tables above), black cells diverged (`div.`, the
# growth factor in the tables) or raised (`err.`). Rows are grouped by plant, columns into baselines
# and the papers' methods; the printed rows first, then the tuned ones.

# %%
TOL = results.Tolerance(
    rtol=max(METHODS[n].tolerance.rtol for n in method_names),
    atol=max(METHODS[n].tolerance.atol for n in method_names),
    reason="the loosest reproduction tolerance of the methods in the table ("
    + "; ".join(f"{n}: {METHODS[n].tolerance.reason}" for n in method_names
                if METHODS[n].tolerance != results.DETERMINISTIC)
    + "; every other method deterministic)")
MATRICES = {kind: matrix.Matrix(SCENARIOS, method_names, {
    (sc.name, n): CELLS[kind][(sc.network.name, sc.attack.name, n)] for sc in SCENARIOS
    for n in method_names}) for kind in KINDS}
for kind in KINDS:
    fig = report.heatmap(MATRICES[kind], width=plotting.PAGE_WIDTH, title=(
        f"Arena, {kind} rows: steady-window score, oracle = 1 ({RUNS} runs: test seeds "
        f"{TEST['seeds'][0]}–{TEST['seeds'][-1]})"))
    plotting.save_figure(fig, FIG_DIR, f"extra_heatmap_{kind}", data=report.columns(MATRICES[kind]),
                         tolerance=TOL)

# %% [markdown]
# ## The API, live: one method on one scenario
#
# Everything above is read from the committed files. The same scores come from one call: here
# ding2020 as printed on the target plant under the bias, a few runs at the cards' seed 2026 (neither
# a validation nor a test seed), scored against the oracle on the same runs
# (`secest.arena.estimators.evaluate`). Paper mode: 4 runs at the plant's own horizon; fast mode 2
# runs of 10 steps (no steady window: a smoke test).

# %%
live = scenarios.scenario("target20", "bias", horizon="auto" if mode == "paper" else 10,
                          runs=4 if mode == "paper" else 2, seed=2026)
with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # the methods' own warnings: said in their notebooks
    live_cells = estimators.evaluate(live, ["oracle", "ding2020"], short=mode != "paper")
for name, s in live_cells.items():
    t = matrix.cell_text(s)
    print(f"{live.name}, {live.runs} runs of {live.horizon} steps, {name}: steady {t['steady']}, "
          f"transient {t['transient']}, detection {t['detection'] or '–'}")

# %% [markdown]
# ## Findings (claims)
#
# Each finding is a measurement with a rule on its interval, stated before this design's first
# run; none says which method should win, and each is reported **per plant** (the plant of a
# method's own paper example marked *home*). They are decided on the **tuned rows** (every method
# under the one registered rule) over the pooled runs of the test seeds; what the same rule gives on
# the **printed rows** is recorded beside it (`measured.printed`), not deciding. No finding is decided
# by a cell that equals the oracle by construction (the oracle; `kf` and `chi2-kf` under no sensor
# attack are centralised filters on the oracle's data). The thresholds are ours: **within a factor
# 2** of the oracle means the upper 95 % bound of the steady-window score is at most 2; a false-alarm
# rate is acceptable when its upper bound is at most 1 %; a detector *sees* an attack when the lower
# bound of its detection rate is at least 50 %.
#
# | id | what is measured, and the rule |
# |---|---|
# | X1 | consistency (a sanity check of the scores, not a finding): no *distributed* method (every method but the oracle and the centralised `kf`, `chi2-kf`, which equal or bound the oracle by construction) scores below the oracle beyond its interval (smallest upper bound $\ge1$), per plant |
# | X2 | without attack, every paper method stays within a factor 2 on every plant (listed per plant, home marked) |
# | X3 | premise of the attack columns: every attack card degrades, on every plant, the undefended baseline it reaches (`kf` under sensor attacks, `consensus-kf` under message and link attacks): lower bound of its score $>1$ and above its no-attack upper bound |
# | X4_&lt;attack&gt; | per attack: the methods within a factor 2 on every plant where the attack degrades its baseline (X3), among the methods the attack can reach (message and DoS: only methods whose nodes exchange messages); holds when a paper method is that is told nothing about the attack and whose estimate the attack touches (the told and the untouched listed beside); `fails-premise` when the attack degrades its baseline on no plant |
# | X5 | applicability: every paper method runs (is not N/A) in every cell; the cells outside each method's theory are counted beside it (a restatement of the one applicability rule on these cards) |
# | X6 | every method with a detector, told nothing about the attack, keeps its false-alarm rate's upper bound at most 1 % in every cell where it runs (the told ones beside) |
# | X7 | every method with a detector, told nothing about the attack, sees every sensor attack on every plant where the attack degrades `kf`: lower bound of its detection rate $\ge50$ % (the told ones beside) |
# | X8 | no method diverges (growth rule, escape, or a non-finite estimate) in any cell |

# %%
FACTOR, FA_MAX, DET_MIN = 2.0, 0.01, 0.5
SECTION = "Findings (claims)"
paper = [n for n in method_names if METHODS[n].kind == "paper"]
others = [n for n in method_names if n != "oracle"]
none_atts = [a for a in ATTACKS if CARDS["attack"][a].kind == "none"]
SENSOR = ("bias", "replacement")


def baseline_of(att: str) -> str:
    return "kf" if CARDS["attack"][att].kind in SENSOR else "consensus-kf"


def plant_label(net: str, name: str) -> str:
    return f"{net} (home)" if METHODS[name].home == net else net


def tolerance_of(names: list[str]) -> results.Tolerance:
    tols = [METHODS[n].tolerance for n in names] or [results.DETERMINISTIC]
    loose = max(tols, key=lambda t: (t.rtol, t.atol))
    return results.Tolerance(max(t.rtol for t in tols), max(t.atol for t in tols), loose.reason)


def cell(net: str, att: str, name: str, kind: str) -> Score:
    return CELLS[kind][(net, att, name)]


def cells_of(name: str, kind: str) -> list[tuple[str, Score]]:
    return [(f"{net}/{att}", cell(net, att, name, kind)) for net in PLANTS for att in ATTACKS]


def x1(kind: str) -> tuple[dict, bool, None]:
    """Per plant, the smallest upper bound of a distributed method's steady score."""
    per_plant = {}
    for net in PLANTS:
        uppers = [(c.steady[2], f"{att}, {n}") for n in others if n not in ("kf", "chi2-kf")
                  for att in ATTACKS if (c := cell(net, att, n, kind)).status == "ok"]
        if uppers:
            low, where = min(uppers)
            per_plant[net] = {"min_upper": low, "cell": where, "cells": len(uppers)}
    low = min((v["min_upper"] for v in per_plant.values()), default=1.0)
    return {"per_plant": per_plant, "min_upper": low}, bool(low >= 1.0), None


def x2(kind: str) -> tuple[dict, bool, None]:
    """Per plant, each paper method's upper bound without attack; outside when above 2 or not scored."""
    m = {"per_plant": {}, "outside": [], "not_scored": {}, "undecided": []}
    for name in paper:
        for net in PLANTS:
            for att in none_atts:
                c = cell(net, att, name, kind)
                label = plant_label(net, name)
                if c.status != "ok":
                    m["not_scored"][f"{name} on {label}"] = c.status + (f": {c.reason}" if c.reason else "")
                    m["outside"].append(name)
                    continue
                suffix = " (home)" if METHODS[name].home == net else ""
                m["per_plant"].setdefault(net, {})[name + suffix] = c.steady[2]
                if c.growth_undecided:  # ‡: the runs do not resolve its growth (Amendment 4)
                    m["undecided"].append(f"{name} on {net}")
                if c.steady[2] > FACTOR:
                    m["outside"].append(name)
    m["outside"] = sorted(set(m["outside"]))
    m["n_outside"] = len(m["outside"])
    return m, m["n_outside"] == 0, None


def felt(net: str, att: str, kind: str) -> bool:
    """X3's rule: the attack degrades its undefended baseline on the plant (or it is not scored)."""
    base = baseline_of(att)
    attacked, clean = cell(net, att, base, kind), cell(net, none_atts[0], base, kind)
    return bool(attacked.status != "ok" or (
        attacked.steady[1] > 1.0 and clean.status == "ok" and attacked.steady[1] > clean.steady[2]))


def x3(kind: str) -> tuple[dict, bool, None]:
    m = {"degrades": {}, "not_degraded": []}
    for att in ATTACKS:
        if CARDS["attack"][att].kind == "none":
            continue
        for net in PLANTS:
            m["degrades"][f"{att} on {net} ({baseline_of(att)})"] = felt(net, att, kind)
            if not felt(net, att, kind):
                m["not_degraded"].append(f"{att} on {net}")
    m["n_not_degraded"] = len(m["not_degraded"])
    return m, m["n_not_degraded"] == 0, None


def told(name: str, att: str) -> bool:
    """Whether the method is told about ``att`` from its card on some plant (`Method.told`)."""
    return any(METHODS[name].told(sc) for sc in SCENARIOS if sc.attack.name == att)


def untouched(name: str, att: str, kind: str) -> bool:
    """Its scores under ``att`` are its no-attack scores to the last digit on every plant: the
    messages the attack falsifies or drops do not enter its estimate (ma2021's zero gain on them,
    W-MSR trimming every neighbour)."""
    pairs = [(cell(net, att, name, kind), cell(net, none_atts[0], name, kind)) for net in PLANTS]
    return all(a.status == b.status == "ok" and a.steady == b.steady for a, b in pairs)


def x4(att: str, kind: str) -> tuple[dict, bool, tuple[str, bool]]:
    """Under ``att``: per reachable method, its largest upper bound over the plants where it bites."""
    sensor = CARDS["attack"][att].kind in SENSOR
    bites = [net for net in PLANTS if felt(net, att, kind)]
    reach = [n for n in others if sensor or METHODS[n].exchanges]
    m = {"plants": bites, "upper": {}, "upper_per_plant": {}, "within": [], "not_scored": [],
         "told": [n for n in reach if told(n, att)],
         "untouched": [n for n in reach if not sensor and untouched(n, att, kind)]}
    for name in reach:
        cs = {net: cell(net, att, name, kind) for net in bites}
        if not cs:
            continue
        if any(c.status != "ok" for c in cs.values()):
            m["not_scored"].append(name)
            continue
        m["upper_per_plant"][name] = {plant_label(net, name): c.steady[2] for net, c in cs.items()}
        m["upper"][name] = max(c.steady[2] for c in cs.values())
        if m["upper"][name] <= FACTOR:
            m["within"].append(name)
    m["paper_within"] = sum(n in paper and n not in m["told"] + m["untouched"] for n in m["within"])
    premise = ("(X3) the attack degrades the undefended baseline on at least one plant", bool(bites))
    return m, bool(m["paper_within"] >= 1), premise


def x5(kind: str) -> tuple[dict, bool, None]:
    m = {"n/a": {}, "outside_theory": {}}
    for name in paper:
        cs = cells_of(name, kind)
        m["n/a"][name] = {s: c.reason for s, c in cs if c.status == "n/a"}
        m["outside_theory"][name] = sum(bool(c.outside) for _, c in cs)
    m["cells"] = len(PLANTS) * len(ATTACKS)
    m["n_na"] = sum(len(v) for v in m["n/a"].values())
    return m, m["n_na"] == 0, None


def detectors(kind: str) -> list[str]:
    return [n for n in others if any(c.false_alarm is not None for _, c in cells_of(n, kind))]


def x6(kind: str) -> tuple[dict, bool, None]:
    m = {"upper": {}, "cell": {}, "told": {}}
    for name in detectors(kind):
        fa = [(c.false_alarm[2], s) for s, c in cells_of(name, kind) if c.false_alarm is not None]
        if any(told(name, att) for att in ATTACKS):  # alarms only where it was told: beside
            m["told"][name] = max(fa)[0]
            continue
        m["upper"][name], m["cell"][name] = max(fa)
    m["worst_upper"] = max(m["upper"].values(), default=0.0)
    return m, bool(m["worst_upper"] <= FA_MAX), None


def x7(kind: str) -> tuple[dict, bool, tuple[str, bool]]:
    sensor_cells = [(att, net) for att in ATTACKS if CARDS["attack"][att].kind in SENSOR
                    for net in PLANTS if felt(net, att, kind)]
    m = {"lower": {}, "cell": {}, "told": {}}
    for name in detectors(kind):
        det = [(c.detection[1], f"{net}/{att}") for att, net in sensor_cells
               if (c := cell(net, att, name, kind)).status == "ok" and c.detection is not None]
        if det and any(told(name, att) for att, _ in sensor_cells):
            m["told"][name] = min(det)[0]  # reported beside, not deciding
        elif det:
            m["lower"][name], m["cell"][name] = min(det)
    m["worst_lower"] = min(m["lower"].values(), default=0.0)
    premise = ("(X3) a sensor attack degrades kf on at least one plant", bool(sensor_cells))
    return m, bool(m["lower"]) and m["worst_lower"] >= DET_MIN, premise


def x8(kind: str) -> tuple[dict, bool, None]:
    cells = {f"{s}, {n}": c.reason for n in others for s, c in cells_of(n, kind)
             if c.status == "diverged"}
    return {"diverged": len(cells), "cells": cells}, not cells, None


def decided(fn, key: str, **text) -> dict:
    """A claim decided on the tuned rows, the printed rows' value and outcome recorded beside it."""
    measured, holds, premise = fn("tuned")
    p_measured, p_holds, p_premise = fn("printed")
    printed = {key: p_measured[key], "holds": bool(p_holds),
               "premise": None if p_premise is None else bool(p_premise[1])}
    return results.claim(measured=measured | {"printed": printed}, holds=holds, premise=premise,
                         key=key, source="ours", runs=RUNS, section=SECTION, **text)


RULE = " Decided on the tuned rows; measured.printed: the same rule on the printed rows (not deciding)."
claims = {}
claims["X1"] = decided(
    x1, "min_upper", threshold=1.0, tolerance=tolerance_of(others),
    paper="(ours) consistency of the arena's scores: no distributed method estimates better than "
    "the oracle (the centralised Kalman filter on clean data) beyond the uncertainty of its score",
    check="per plant, the smallest upper 95 % bootstrap bound of a steady-window network score over "
    "every scored cell, every method except the oracle, kf and chi2-kf (centralised: kf equals the "
    "oracle without a sensor attack by construction); holds when >= 1 on every plant. A sanity "
    "check of the scores (consensus with many rounds tends to the oracle), not a finding about "
    "the methods: it fails only through an error of the scoring or by chance." + RULE)
claims["X2"] = decided(
    x2, "n_outside", threshold=FACTOR, tolerance=tolerance_of(paper),
    paper="(ours) without attack, the papers' defences cost little accuracy: every paper method "
    "keeps its steady-window score within a factor 2 of the oracle on every plant",
    check="per plant and paper method, the upper 95 % bound of its steady-window network score on "
    "the attack-free scenario (home plants marked); a cell not scored (N/A, diverged, error) counts "
    "as outside; holds when no paper method is outside." + RULE)
claims["X3"] = decided(
    x3, "n_not_degraded", threshold=1.0, tolerance=tolerance_of(["kf", "consensus-kf"]),
    paper="(ours) premise of the attack columns: every attack card measurably degrades, on every "
    "plant, the undefended baseline it reaches, so that each attack cell tests something",
    check="per attack and plant: the lower 95 % bound of the steady-window score of kf (sensor "
    "attacks) or consensus-kf (message and link attacks) under the attack exceeds 1 and its upper "
    "bound without attack (or the baseline is not scored: diverged); holds when every cell does." + RULE)
for att in ATTACKS:
    if CARDS["attack"][att].kind == "none":
        continue
    claims["X4_" + re.sub(r"\W", "", att)] = decided(
        lambda kind, att=att: x4(att, kind), "paper_within", threshold=FACTOR,
        tolerance=tolerance_of(others),
        paper=f"(ours) under the attack '{att}' ({CARDS['attack'][att].title}), at least one paper "
        "method keeps its steady-window score within a factor 2 of the oracle on every plant where "
        "the attack degrades the undefended baseline",
        check="per method the attack reaches (message and DoS: methods whose nodes exchange "
        "messages), the upper 95 % bound of its steady-window score per plant where X3 finds the "
        "attack felt, and the largest; 'within' lists those <= 2, 'not_scored' those N/A, diverged "
        "or failing on one of them; holds when a paper method is within that is told nothing "
        "about the attack ('told': Method.told, from the card, its paper's assumption) and whose "
        "estimate the attack touches ('untouched': scores equal to its no-attack scores on every "
        "plant, the falsified or lost messages not entering it); both listed, not deciding; "
        "fails-premise when the attack is felt on no plant." + RULE)
claims["X5"] = decided(
    x5, "n_na", threshold=0,
    paper="(ours) applicability: every paper method runs in every cell of the cross (N/A only "
    "where a method cannot run at all; cells outside its theory are scored and marked)",
    check="per paper method, the cells where a requirement fails (Method.requirements, N/A) and "
    "the number of scored cells outside its theory (Method.conditions); holds when no paper "
    "method is N/A anywhere. It restates the applicability rule on these cards: it fails only "
    "where a paper method's design does not exist on a card (a rank condition, an infeasible "
    "LMI, no Hurwitz gain), which none of these cards meets." + RULE)
claims["X6"] = decided(
    x6, "worst_upper", threshold=FA_MAX, tolerance=tolerance_of(detectors("tuned")),
    paper="(ours) the detectors rarely raise false alarms: every method with a detector keeps its "
    "false-alarm rate below 1 % in every scenario where it runs",
    check="per method with alarms, the largest upper 95 % bound (union of Wilson and a bootstrap "
    "over runs) of its false-alarm rate on the steady window over every cell; holds when every one "
    "is <= 1 %. A method told the attack (Method.told: guo2023 alarms only on the sensor it is "
    "told, so its rate over every node is diluted) is listed beside ('told'), not deciding." + RULE)
claims["X7"] = decided(
    x7, "worst_lower", threshold=DET_MIN, tolerance=tolerance_of(detectors("tuned")),
    paper="(ours) every method with a detector sees the sensor attacks: it flags at least half of "
    "the attacked samples under the bias and the replacement on every plant where they degrade kf",
    check="per method with alarms told nothing about the sensor attacks (Method.told), the "
    "smallest lower 95 % bound of its detection rate over the sensor-attack cells where X3 finds "
    "the attack felt ('told': the same for the told ones, not deciding); holds when every one "
    "is >= 50 %." + RULE)
claims["X8"] = decided(
    x8, "diverged", threshold=0,
    paper="(ours) no method diverges on the shared scenarios",
    check="number of cells that are diverged: an estimate not finite, a node whose mean squared "
    "normalised error grows as k^p over the steady window with the lower bound of p (95 % "
    "together over the nodes) above 0.05 (on the pooled runs of the test seeds), or a steady-window RMS error over the pooled runs "
    "above 1e4 times the oracle's (protocol.toml, Amendments 2 and 3); holds when 0." + RULE)

written = json.loads(results.write_claims(results_path, claims).read_text())
for cid, c in written.items():
    print(f"{cid}: {c['verdict']} on the tuned rows (printed rows: "
          f"{'holds' if c['measured']['printed']['holds'] else 'does not hold'})")

# %% [markdown]
# ## What the test seeds show
#
# Written from the measurements above (nothing in this section is typed by hand): per plant, the
# paper methods' steady-window scores without attack, printed and tuned, the home plant marked; the
# diverged rows; then each finding's outcome.


# %%
def upper_text(c: Score) -> str:
    if c.status == "ok":
        return matrix._sig(c.steady[2])
    return "diverged" if c.status == "diverged" else c.status


lines = []
for net in PLANTS:
    parts = []
    for name in paper:
        pr, tu = (cell(net, none_atts[0], name, k) for k in KINDS)
        home = " (**home**)" if METHODS[name].home == net else ""
        parts.append(f"`{name}`{home} {upper_text(pr)} → {upper_text(tu)}")
    lines.append(f"* **{net}** (`{TEST['plants'][net]['plant']}`), no attack, upper 95 % bound of the "
                 "steady score, printed → tuned: " + "; ".join(parts) + ".")
for kind in KINDS:
    gone = [f"{n} on {s}" for n in paper for s, c in cells_of(n, kind) if c.status == "diverged"]
    lines.append(f"* Paper-method cells diverged, {kind} rows: {len(gone)} of "
                 f"{len(paper) * len(PLANTS) * len(ATTACKS)}" + (f" ({'; '.join(gone)})." if gone else "."))
lines += [f"* {cid}: **{c['verdict']}** on the tuned rows." for cid, c in written.items()]
display(Markdown("\n".join(lines)))

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
# | A10 | settings | every method twice: as its paper printed it (ding2020's $\kappa$ and threshold, lee2020's $\kappa,\gamma$, li2025's weights, ma2021's $p$; the baselines at their textbook defaults) and tuned by the registered rule of `protocol.toml` on the validation seeds; ma2021's recursion (30) holds its gains once $P_k$ settles (relative change $\le10^{-6}$ on ten steps) | issue #28: tuning matters as much as the method, so both rows are reported; the rule, search sets and seed split were committed before the test seeds ran. What the rule can and cannot do: its objective is the attack-free score, so constants that act only under attack are not tuned by it (guo2023's alarm level and ma2021's $p$ leave the attack-free estimate unchanged, li2025's weights move it by less than 0.1 %: their tuned rows are the printed ones by the tie rule), and a detector's threshold is held only by the false-alarm cap, so the rule takes the laxest level that meets it, not the one that detects best |
# | A11 | falsified messages | a shift of 20 oracle steady-state sd of the state estimate a node sends, mapped into each method's message by its own encoding | one attack for every method, in physical units (the first design added a bounded injection in each method's own message units, which made the columns incomparable); a method with several consensus rounds sends several messages per link and step, and a falsified link falsifies each of them (more exchanges, more surface: `consensus-kf`'s message score grows with its rounds) |
# | A12 | seeds | the eight test seeds 301–308 `protocol.toml` registers (Amendment 4; 201–208 before it), 40 runs each (320 pooled), their runs pooled (one $\Sigma_o$, one bootstrap, one growth rule over all of them); the first test stage ran only 201–204 (a declared deviation, for CPU; ERRATA.md, arena); the cards' seed 2026 only in the live cell | a finding does not hinge on one draw of the runs; the validation seeds 101–104 only chose the tuned constants |
# | A13 | Amendment 2 of the protocol, and of the findings | made **after** the first test stage (`figures/arena/test.json` at commit 367ae54, tuned constants a141056) was looked at: a run that escapes (RMS error above $10^4$ times the oracle's) makes its cell diverged; the growth factor is 2, not 4; the tuning's fallback never picks a diverged point unless all diverged; `kcf`'s $\epsilon\,d_{\max}<1$ is a condition, not a requirement; every baseline declares its attack model (marks one rule for all); ding2020's overflowing bounds give non-finite estimates (diverged), not an error; X4, X6 and X7 decide on the methods told nothing about the attack and (X4) touched by it. Then the validation re-ran in full and this test stage on all eight seeds | defects of the first stage a hostile fairness review found: a ratio of $1.6\cdot10^{29}$ scored, an error growing linearly read as a score, a tuned point that had diverged, an N/A that was a stability condition, marks on the papers only, a divergence reported as an error, and findings decided by methods told the attack or immune to it by construction; ERRATA.md gives the first stage's results beside these |
# | A14 | replacement | the replaced value is uniform in ±`magnitude` noise sd around 0, as li2025's attack model replaces the measurement by a bounded signal; on the target, whose position grows to thousands of noise sd over the horizon, a replaced sample is therefore a gross error, while on the three-inertia and the tank (outputs of the order of the range) it is not | the attack is one card in noise units, but its strength relative to the signal differs by plant: the replacement column on `target20` measures that plant's output scale as much as the methods (a replacement around the true output would be an additive attack, outside li2025's model) |
# | A15 | Amendment 3 of the protocol | made **after** the second test stage (`figures/arena/test.json` at commit 76e690b, tuned constants d417302) was looked at: the tuning pools each point's validation seeds by the test stage's own function (one $\Sigma_o$, one growth rule, one escape rule; the objective the pooled score, not the median of the seeds'); divergence by the growth exponent of every node with a 95 % interval over the runs, a cell diverged when some node's lower bound exceeds $0.05$ (before: the network's factor above 2); escape on the pooled runs (before: any one run); rule 4's ties to the least growth. Then the validation re-ran in full and this test stage on all eight seeds | defects of the second stage a second hostile review found: one point diverged in the tuning (judged per seed, 40 runs) and bounded in the test (pooled, 320 runs); a factor limit that passes an error growing as $k$ (a random walk) and hides one node's growth behind the network mean; an escape rule whose power grew with the run count; a fallback tie decided by the listing order. ERRATA.md gives the second stage's results beside these |
# | A16 | Amendment 4 of the protocol | made **after** the third test stage (`figures/arena/test.json` at 9e07aa0, tuned constants aedc436, seeds 201–208) was looked at: the seeds 201–208 retired and the test stage run on eight new seeds 301–308; ‡ two-sided (some node's upper bound of $p$ above $0.05$: neither growth nor boundedness shown; before, only a factor above the limit with an interval that was not); every row stores its growth interval, diverged rows too (to 4 significant digits); rule 4's ties read the most growing node. The divergence rule and its limit unchanged. The validation re-ran in full (the same statuses, scores and choices as aedc436, now with the growth fields) and this test stage on the new seeds | a third hostile review found the limit below what the runs resolve (`local-kf`'s random walk on the three-inertia plant, $p = 0.082$ exactly, ruled diverged on the validation runs and scored unmarked on the test runs), a one-sided mark that let a wide interval read as bounded, diverged verdicts that the files could not show, and test seeds seen under three versions of the rules. ERRATA.md gives the third stage's results beside these |

# %%
manifest_path = run.finish(extra={"tuned": TEST["tuned"], "protocol": TEST["protocol"]})
print("run manifest:", manifest_path.relative_to(results.repo_root()))

"""Example (b): a sixth method (my_method.py) registered and raced, on one's own plant and one
of the package's (target20, ding2020's target tracked by 20 sensors)."""

import sys
from pathlib import Path

from secest.arena import race

here = Path(__file__).parent
sys.path.insert(0, str(here))  # my_method.py sits next to this file
from my_method import FixedGainKF  # noqa: E402

m = race(cards=here / "my_cards.toml", methods=[FixedGainKF, "kf", "chi2-kf", "guo2023"],
         plants=["oscillator6", "target20"], attacks=["none", "bias2"], runs=5, horizon=50, short=True,
         out=here / "results-method")
for sc in m.scenarios:
    print(f"{sc.name:18} fixed-gain-kf: {m.cell(sc.name, 'fixed-gain-kf').status}")

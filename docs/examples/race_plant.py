"""Example (a): a plant and a network of one's own (my_cards.toml) raced against every method."""

from pathlib import Path

from secest.arena import race

here = Path(__file__).parent
m = race(cards=here / "my_cards.toml", plants=["oscillator6"], attacks=["none", "bias", "bias2"],
         runs=5, horizon=50, short=True,
         out=here / "results-plant")
for name in m.methods:
    print(f"{name:14} {m.cell('oscillator6/bias2', name).status}")

# (a) your plant and network (my_cards.toml) against every registered method
# (--horizon 50 --short: a smoke test that runs in seconds; without them each plant runs
#  20 of its time constants and is scored on its steady window)
python -m secest.arena --cards my_cards.toml --plants oscillator6 --attacks none,bias,bias2 \
    --runs 5 --horizon 50 --short --out results-plant

# (b) your method (my_method.py) registered from its file and raced with three others
python -m secest.arena --cards my_cards.toml --method my_method.py:FixedGainKF \
    --methods fixed-gain-kf,kf,chi2-kf,guo2023 --plants oscillator6,target20 --attacks none,bias2 \
    --runs 5 --horizon 50 --short --out results-method

# what can be raced: the cards (the package's and yours) and the registered methods
python -m secest.arena --cards my_cards.toml --method my_method.py:FixedGainKF --list

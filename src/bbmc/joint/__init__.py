"""One rock joint from its Barton-Bandis parameters, assembled from the laws of `bbmc.laws`.

`model`: the paper's parameter sets (eqs 2-18) and their errata; `curves` and `figures`: the tables and
drawings of `bbmc joint`.
"""

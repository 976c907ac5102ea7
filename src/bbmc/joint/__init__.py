"""One rock joint from its Barton-Bandis parameters, assembled from the laws of `bbmc.laws`.

`inputs`: the full joint's keys as a config gives them and their checks, shared by the scene's law and
`bbmc joint`; `derived`: its inputs at the field length (scaled JRC and JCS, phi_r, delta_peak, K_ni,
V_m), one function for the engine, the slope and `bbmc joint`; `model`: the paper's parameter sets
(eqs 2-18) and their errata; `curves` and `figures`: the tables and drawings of `bbmc joint`.
"""

"""Wedge failure of a rock slope: two joint planes, the face and the upper surface (Hoek & Bray 1981,
ch. 8; Wyllie & Mah 2004, ch. 7; Rocscience Swedge).

* ``geometry``: the wedge's vertices, line of intersection, normals, areas, volume, trace lengths and
  heights, for one wedge or arrays of wedges (``wedge_geometry``, ``wedge_geometries``);
* ``short_solution``: Hoek & Bray's short-solution angles, factors X, Y, A, B and wedge factor K;
* ``vectors``: the stacked 3-vector algebra both use;
* ``mechanics``: the vector solution (the active resultant, normal reactions, sliding mode, FS);
* ``loads``: water (Hoek & Bray's, no crack), seismic and force vectors;
* ``water``: the water models (dry, Hoek & Bray's with or without a tension crack, filled fraction,
  given pressures per plane);
* ``essentials``: the compiled fast path of the geometry (what the mechanics needs, no crack);
* ``analysis``: from the inputs to geometry, loads, mode and FS in one call (``analyse_wedges``).
* ``strength``: Barton-Bandis per plane at its own normal stress (scale, waviness, tangent c and phi);
* ``support``: bolts (active, passive) and shotcrete; ``design``: the optimum bolt and the least force;
  ``bolting``: the bolts of one case for a target FS, checked by the vector solution;
* ``size_limits``: Swedge's bench width, slope length, trace length, persistence and volume limits, as
  a scaling of the wedge about its toe;
* ``cases``: one wedge case from its setting and two planes; ``combinations``: every pair of sets;
* ``probability``: Fisher-scattered planes and P_f (the `bbmc sweep` wedge base's model);
* ``config``: the keys of `bbmc wedge`'s joint planes, strengths, water, loads and design, in SI.
"""

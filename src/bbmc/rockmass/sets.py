"""A joint set cut by the slope's cross-section: the orientation of each of its lines in the section,
and the spacing of its traces there.

The section is vertical, x pointing into the slope (the face looks towards -x), y up. A plane of dip d
whose dip direction makes b with the direction the face looks has its trace in the section at the
apparent dip tan(psi) = tan(d) |cos(b)|, and traces of planes a true spacing S apart lie
S / sqrt(1 - sin^2(d) sin^2(b)) apart in the section (`bbmc.geometry.orientation.section_traces`). A set
given in 3D (dip, dip direction, Fisher's K) is sampled pole by pole on the sphere and each sampled
plane is cut by the section: the scatter reaches the section through the same projection.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from bbmc.geometry.orientation import SectionTraces, plane_of_pole, section_traces, upward_pole
from bbmc.rockmass import config as c
from bbmc.rockmass import distributions


def mean_trace(joint_set: c.JointSet, section_azimuth_deg: float | None) -> SectionTraces:
    """The set's mean orientation in the section (the scatter left out)."""
    if joint_set.orientation is not None:
        o = joint_set.orientation
        return section_traces(np.array([o.dip_deg]), np.array([o.dip_direction_deg - section_azimuth_deg]))
    mean = joint_set.dip_deg.mean if isinstance(joint_set.dip_deg, c.DipScatter) else joint_set.dip_deg
    return section_traces(np.array([mean]), np.array([joint_set.dip_direction_to_face_deg or 0.0]))


def sample_traces(
    joint_set: c.JointSet, section_azimuth_deg: float | None, streams: list[np.random.Generator]
) -> SectionTraces:
    """The orientations of the set's lines, one drawn from each line's stream: a 3D set's poles from
    Fisher's distribution about its mean pole (`scipy.stats.vonmises_fisher`); a set in the section,
    its dips from the dip's distribution (normal), its dip direction fixed."""
    count = len(streams)
    if joint_set.orientation is not None:
        o = joint_set.orientation
        if o.fisher_k is None:
            dip, direction = np.full(count, o.dip_deg), np.full(count, o.dip_direction_deg)
        else:
            fisher = stats.vonmises_fisher(upward_pole(o.dip_deg, o.dip_direction_deg), o.fisher_k)
            poles = np.array([fisher.rvs(1, random_state=rng)[0] for rng in streams]).reshape(-1, 3)
            dip, direction = plane_of_pole(poles)
        return section_traces(dip, direction - section_azimuth_deg)
    spread = distributions.dip(joint_set.dip_deg)
    dip = np.array([spread.rvs(size=1, random_state=rng)[0] for rng in streams]).reshape(-1)
    return section_traces(dip, np.full(count, joint_set.dip_direction_to_face_deg or 0.0))

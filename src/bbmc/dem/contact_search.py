"""The contact search: the facing edge pairs within the search margin, found between cycles; a
contact found before keeps its state, a new one gets its joint type (the first contact rule that
matches its blocks' groups, its dip and its edges' labels) and its initial state.

The search is a computational device, and what it finds must not change an answer. So a contact that
still holds a bond (a share that has neither slipped nor failed in tension, with cohesion or tensile
strength: intact rock, a cemented joint) is kept whether or not the search finds it again: it opens
only as far as its bond lets it (T / K_n, which can be more than a small margin) and goes only by
breaking. A contact that the search's corner rule would drop (a corner makes one contact with a face:
`detection.facing_edges`) is kept while it carries a load (a share in compression, or a bond): that rule
is a choice at the search, and dropping a loaded contact at one search but not at another made a run
depend on when it searched. Other contacts the search no longer finds are dropped (open ones, and
edges that have slid past a joint's end, deeper than the blocks overlap).

Intact rock that first comes into contact after the initial assembly (two blocks that met corner to
corner and slid onto each other's faces) was never bonded: it is born the joint it breaks into."""

from __future__ import annotations

import time

import numpy as np

from bbmc.dem import contact_forces, joint_state, kernels
from bbmc.dem import layout as L
from bbmc.dem.detection import CORNER_REPLACED, candidate_pairs, facing_edges
from bbmc.dem.model import Model
from bbmc.dem.state import State


def _joint_types(model: Model, found: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The joint law of each new contact: the first matching rule, else the default. The dip is that of
    the contact's common line (`normal`: the face a corner presses on); a rule with `edges` matches a
    contact one of whose edges carries that label."""
    dip = np.arctan2(np.abs(normal[:, 0]), np.abs(normal[:, 1]))
    ga, gb = model.block_group[found[:, 2]], model.block_group[found[:, 3]]
    types = np.full(len(found), model.default_law, dtype=np.int64)
    open_ = np.ones(len(found), dtype=bool)
    label_a, label_b = model.edge_label[found[:, 0]], model.edge_label[found[:, 1]]
    rules = zip(model.rule_groups, model.rule_dip, model.rule_law, model.rule_edges, strict=True)
    for (g1, g2), (lo, hi), law, edges in rules:
        match = open_ & (dip >= lo - 1e-12) & (dip <= hi + 1e-12) & (edges[label_a] | edges[label_b])
        if g1 >= 0:
            match &= ((ga == g1) & (gb == g2)) | ((ga == g2) & (gb == g1))
        types[match] = law
        open_ &= ~match
    return types


def _born_types(model: Model, state: State, found: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """`_joint_types` of contacts new at this search; after the initial assembly, a type of intact rock
    is replaced by the joint it breaks into."""
    types = _joint_types(model, found, normal)
    if state.step == 0:
        return types
    joint = model.laws[types, L.BREAKS_INTO]
    return np.where(joint >= 0, joint, types)


def _shares_any(state: State, share: np.ndarray) -> np.ndarray:
    """Whether any share of each contact satisfies `share` (a bool per sub-contact row)."""
    return share.reshape(-1, state.n_sub).any(axis=1)


def _bonded(state: State) -> np.ndarray:
    """Whether each contact has a share that still holds a bond: neither slipped nor broken, with
    cohesion or tensile strength."""
    subs = state.subs
    return _shares_any(state, (subs[:, L.SLIPPED] == 0.0) & ((subs[:, L.COH] > 0.0) | (subs[:, L.TEN] > 0.0)))


def _kept_then_zeros(rows: np.ndarray, kept: np.ndarray, new: int) -> np.ndarray:
    """rows[kept] followed by `new` rows of zeros, gathered straight into the one new array: indexing
    then concatenating held a third copy of the sub-contact rows at each search (104 MB at 100,000
    blocks). mode="clip" because numpy buffers `out` for mode="raise"; `kept` are valid row indices."""
    out = np.zeros((len(kept) + new, rows.shape[1]))
    np.take(rows, kept, axis=0, out=out[: len(kept)], mode="clip")
    return out


def search_contacts(model: Model, state: State) -> None:
    """Find the facing edge pairs now within the margin; contacts found before keep their state."""
    b, economy = state.blocks, model.economy
    immobile = state.immobile if economy.skip_immobile_pairs else np.zeros(len(b), dtype=bool)
    pairs = candidate_pairs(state.world, model.vertex_start, immobile, model.search_margin)
    found, normal = _facing_edges(model, state, pairs)
    n_vertices, n_sub = len(model.local), state.n_sub
    old_keys = state.contacts[:, L.EDGE_A] * n_vertices + state.contacts[:, L.EDGE_B]
    status, found = found[:, 4], found[:, :4]
    new_keys = found[:, 0] * n_vertices + found[:, 1]
    order = np.argsort(old_keys, kind="stable")
    slot = np.searchsorted(old_keys[order], new_keys)
    known = slot < len(order)
    known[known] = old_keys[order][slot[known]] == new_keys[known]
    old = order[slot[known]]
    loaded = _bonded(state) | _shares_any(state, state.subs[:, L.SN] > 0.0)
    stays = (status[known] != CORNER_REPLACED) | loaded[old]
    bonded = np.flatnonzero(_bonded(state))
    kept = np.union1d(old[stays], bonded[~np.isin(old_keys[bonded], new_keys)])
    fresh = (~known) & (status != CORNER_REPLACED)
    contacts = np.concatenate(
        [
            state.contacts[kept],
            np.column_stack([found[fresh], _born_types(model, state, found[fresh], normal[fresh])]).astype(
                np.int64
            ),
        ]
    ).reshape(-1, L.CONTACT_COLUMNS)
    fresh = found[fresh]
    kept_rows = (kept[:, None] * n_sub + np.arange(n_sub)).ravel()
    subs = _kept_then_zeros(state.subs, kept_rows, len(fresh) * n_sub)
    law_state = _kept_then_zeros(state.law_state, kept_rows, len(fresh) * n_sub)
    first_new = len(kept)
    joint_state.initial_joint_state(
        contacts, subs, law_state, n_sub, model.laws, model.params, first_new, state.step == 0
    )
    if state.step == 0:  # intact rock (a type that breaks into a joint) keeps joint water out
        intact = model.laws[contacts[first_new:, L.JOINT_TYPE], L.BREAKS_INTO] >= 0
        state.dry_edges[contacts[first_new:][intact][:, [L.EDGE_A, L.EDGE_B]].ravel()] = True
    new_contacts, new_subs, new_law_state = (
        contacts[first_new:],
        subs[first_new * n_sub :],
        law_state[first_new * n_sub :],
    )
    if model.variable_laws:
        joint_state.update_joint_laws(
            new_contacts,
            new_subs,
            new_law_state,
            n_sub,
            model.laws,
            model.params,
            model.economy.changed_laws_only,
        )
    contact_forces.contact_forces(
        b,
        state.world,
        model.vertex_next,
        new_contacts,
        new_subs,
        new_law_state,
        n_sub,
        model.laws,
        model.params,
        0.0,
        False,
        state.per_contact,
    )
    state.contacts, state.subs, state.law_state = contacts, subs, law_state
    if state.threads > 1:
        state.per_contact = np.zeros((len(contacts), 4))
        state.block_start, state.block_contacts = kernels.block_contacts_of(contacts, len(b))
    b[:, [L.XR, L.YR, L.THR]] = b[:, [L.X, L.Y, L.TH]]
    state.searches += 1


def _facing_edges(model: Model, state: State, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`detection.facing_edges` of the block pairs, in calls paced by `state.search_pace`: each pair's
    edges are found alone, so the pieces joined are the edges of one call, in the same order."""
    pieces, start = [], 0
    while True:
        stop = start + state.search_pace.take(len(pairs) - start)
        started = time.perf_counter()
        pieces.append(
            facing_edges(
                pairs[start:stop],
                state.world,
                model.vertex_start,
                model.vertex_next,
                state.blocks[:, L.SIZE],
                model.search_margin,
                model.economy.bound_depth_when_needed,
            )
        )
        state.search_pace.timed(stop - start, time.perf_counter() - started)
        start = stop
        if start == len(pairs):
            return np.concatenate([f for f, _ in pieces]), np.concatenate([n for _, n in pieces])

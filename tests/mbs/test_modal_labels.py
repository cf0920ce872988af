"""Labels of repeated modes: a repeated eigenvalue's shapes are any basis of its subspace, so the
kernel localises them on coordinates before labelling (:func:`ddgsa.mbs.modal.localised`)."""

from __future__ import annotations

import numpy as np

from ddgsa.mbs.modal import modal_analysis


def test_two_identical_oscillators_get_one_label_each_whatever_the_eigensolver_mixes() -> None:
    # two uncoupled, identical 1-DOF oscillators (omega = 10 rad/s) and a third at 20 rad/s: the first
    # eigenvalue is double, its eigenvectors an arbitrary mix of the two coordinates without localisation
    m = np.eye(3)
    k = np.diag([100.0, 100.0, 400.0])
    c = 0.01 * k
    rot = np.array([[np.cos(0.7), -np.sin(0.7), 0.0], [np.sin(0.7), np.cos(0.7), 0.0], [0.0, 0.0, 1.0]])
    # the same system in rotated coordinates stays diagonal in its first two: a pure mix of the pair
    table = modal_analysis(rot.T @ m @ rot, rot.T @ c @ rot, rot.T @ k @ rot, ["a", "b", "c"],
                           {"a": "first", "b": "second", "c": "third"}, basis=rot, m_full=m)
    assert np.allclose(table["frequency_hz"], [10 / (2 * np.pi)] * 2 + [20 / (2 * np.pi)])
    assert sorted(table["label"][:2]) == ["first", "second"] and table["label"][2] == "third"
    for j in (0, 1):                                              # each shape on one coordinate only
        assert max(table.loc[j, "share_first"], table.loc[j, "share_second"]) > 1 - 1e-9

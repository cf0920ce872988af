"""Rig parameter declarations: complete, consistent, and the faults healthy at nominal."""

from __future__ import annotations

import math

import pytest

from ddgsa.models.hss_rig.parameters import FAULTS, PARAMETERS, SOURCES


def test_every_parameter_is_declared_once_with_unit_range_and_source():
    names = [p.name for p in PARAMETERS]
    assert len(names) == len(set(names))
    for p in PARAMETERS:
        assert p.unit and p.description and SOURCES[p.name], p.name
        assert p.low <= p.nominal <= p.high, p.name


def test_faults_are_healthy_at_nominal_and_can_be_raised():
    by_name = {p.name: p for p in PARAMETERS}
    for f in FAULTS:
        p = by_name[f]
        assert "FAULT" in p.description and p.high > p.nominal
    assert all(by_name[f].nominal == 0.0 for f in FAULTS if f != "eccentric_mass")


def test_disk_inertias_follow_from_its_declared_size():
    """Steel disk 0.25 m x 0.039 m: m = rho pi r^2 h, Ip = m r^2 / 2, Id = m r^2 / 4 + m h^2 / 12 (0.5 %)."""
    by_name = {p.name: p.nominal for p in PARAMETERS}
    r, h, rho = 0.125, 0.039, 7850.0
    m = rho * math.pi * r * r * h
    assert by_name["disk_mass"] == pytest.approx(m, rel=5e-3)
    assert by_name["disk_polar_inertia"] == pytest.approx(m * r * r / 2, rel=5e-3)
    assert by_name["disk_diametral_inertia"] == pytest.approx(m * r * r / 4 + m * h * h / 12, rel=5e-3)

"""Bearing defect frequencies against the published 6205 orders; the outer-race impulse train."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ddgsa.errors import ModelError
from ddgsa.models.hss_rig.bearing import SKF_6205, BearingGeometry, defect_impulses


def test_6205_defect_orders_match_the_published_values():
    """CWRU bearing data centre, 6205-2RS JEM SKF: defect frequencies as multiples of the shaft speed
    (BPFI 5.4152, BPFO 3.5848, FTF 0.39828, BSF 2.357); they are given to 4-5 digits (5e-4)."""
    assert float(SKF_6205.bpfi()) == pytest.approx(5.4152, rel=5e-5)
    assert float(SKF_6205.bpfo()) == pytest.approx(3.5848, rel=5e-5)
    assert float(SKF_6205.ftf()) == pytest.approx(0.39828, rel=2e-4)
    assert float(SKF_6205.bsf()) == pytest.approx(2.357, rel=5e-4)


def test_defect_frequencies_obey_the_kinematic_identities():
    """BPFO + BPFI = n f_r; BPFO = n FTF (independent of the formulas' common factor); linear in speed."""
    g = BearingGeometry(rolling_elements=13, element_diameter=0.012, pitch_diameter=0.065, contact_angle=0.26)
    f_r = np.array([5.0, 25.0])
    np.testing.assert_allclose(g.bpfo(f_r) + g.bpfi(f_r), 13 * f_r, rtol=1e-14)
    np.testing.assert_allclose(g.bpfo(f_r), 13 * g.ftf(f_r), rtol=1e-14)
    # angular contact: d/D cos(alpha) by hand
    r = 0.012 / 0.065 * math.cos(0.26)
    assert float(g.bpfi(25.0)) == pytest.approx(13 * 25 / 2 * (1 + r), rel=1e-14)


def test_impulse_train_has_one_impact_per_ball_pass():
    f_r = 25.0                                          # 1500 rpm
    t = np.arange(0.0, 2.0, 1e-5)
    force = defect_impulses(t, 2 * math.pi * f_r * t, SKF_6205, amplitude=100.0, width=2e-4, jitter=0.0)
    starts = np.flatnonzero((force[1:] > 0) & (force[:-1] == 0))
    assert starts.size == math.floor(2.0 * float(SKF_6205.bpfo(f_r))) + 1     # t = 0 and 179 more in 2 s
    np.testing.assert_allclose(np.diff(t[starts]), 1 / float(SKF_6205.bpfo(f_r)), atol=1.1e-5)
    assert force.max() == pytest.approx(100.0, rel=1e-3)
    # jitter is seeded: same seed, same train; healthy (0) is exactly zero
    a = defect_impulses(t, 2 * math.pi * f_r * t, SKF_6205, 100.0, 2e-4, jitter=0.01, seed=3)
    b = defect_impulses(t, 2 * math.pi * f_r * t, SKF_6205, 100.0, 2e-4, jitter=0.01, seed=3)
    np.testing.assert_array_equal(a, b)
    assert not np.any(defect_impulses(t, 2 * math.pi * f_r * t, SKF_6205, 0.0, 2e-4))


def test_bad_geometry_is_refused():
    with pytest.raises(ModelError, match="'element_diameter' must be in"):
        BearingGeometry(element_diameter=0.05, pitch_diameter=0.04)
    with pytest.raises(ModelError, match="'rolling_elements' must be an integer >= 3"):
        BearingGeometry(rolling_elements=2)

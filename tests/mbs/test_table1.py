"""Seed 000 Table 1 from the kernel's FE shaft modes (issue 17).

The table's rows come out for a *solid* steel shaft of radius 0.3258 m (E = 200 GPa, nu = 0.3,
rho = 7850 kg/m^3: handbook steel) with thin-disc end inertias about radii 7 m (hub, 40 t) and
0.5 m (generator, 30 t), each family under the boundary conditions of the seed's §2.5:
bending on rigid supports at L1 = 1 m and L2 = 5 m with the end masses and diametral inertias,
torsion free-free with the polar inertias, elongation free with the front bearing's axial spring
(k_front_x = 1e10 N/m of Table 2), whose first mode (49.9 Hz, the shaft bouncing on the spring)
the table does not list. Table 2's EI and shaft mass disagree with this shaft. The shaft and its end
inertias are the direct drive's ``shaft: table1`` reading (``tests/models/test_direct_drive_shaft.py``
checks the model's modes under it against Table 1 and a closed form).
"""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import Ground, Spherical, System, TransverseBearing, modes
from ddgsa.mbs.beam import BeamSpec, shaft_modes
from ddgsa.mbs.bodies import FlexibleBody
from ddgsa.models.direct_drive import shaft_parameters
from ddgsa.models.seed_readings import TABLE1_HZ as TABLE1, table1_spec

P = {p.name: p.nominal for p in shaft_parameters("table1")}      # the direct drive's `shaft: table1` reading
L1, L2 = P["front_bearing_x"], P["rear_bearing_x"]


def table1_shaft(axial_spring: float | None = 1e10) -> BeamSpec:
    """Table 1's problem (``seed_readings.table1_spec``) on the ``table1`` shaft, meshed finely (5 cm)."""
    return table1_spec(P, axial_spring)


def test_table1_bending_and_torsion_rows() -> None:
    """Measured: bending +0.01 % / +0.17 %, torsion 0.00 % / -0.04 %."""
    md = shaft_modes(table1_shaft(), n_axial=3, n_torsion=2, n_bending=2)
    np.testing.assert_allclose(md.freq_bending, TABLE1["bending"], rtol=5e-3)
    np.testing.assert_allclose(md.freq_torsion, TABLE1["torsion"], rtol=5e-3)


def test_table1_axial_row_needs_the_front_bearing_spring() -> None:
    """Axial row: modes 2 and 3 of the free shaft on the k_front_x spring (measured 0.00 % / -0.04 %)."""
    md = shaft_modes(table1_shaft(1e10), n_axial=3)
    assert md.freq_axial[0] == pytest.approx(49.9, abs=0.1)
    np.testing.assert_allclose(md.freq_axial[1:], TABLE1["axial"], rtol=5e-3)
    held = shaft_modes(table1_shaft(None), n_axial=2).freq_axial        # held at L1: 99 / 203 Hz, not the table
    assert held[0] < 0.8 * TABLE1["axial"][0]


def test_flexible_body_on_rigid_supports_reproduces_bending_row() -> None:
    """The FFR body of those shapes (lumped masses) on a spherical and a transverse bearing: the same row."""
    shaft = FlexibleBody.shaft("shaft", table1_shaft(), fields=("bending_y_1", "bending_y_2", "bending_z_1",
                                                                 "bending_z_2"), rotary_inertia=False)
    ground = Ground()
    sys_ = System([shaft], constraints=[Spherical(shaft.marker((L1, 0, 0)), ground.marker((L1, 0, 0))),
                                        TransverseBearing(shaft.marker((L2, 0, 0)), ground.marker((L2, 0, 0)))])
    f = modes(sys_)["frequency_hz"].to_numpy()
    np.testing.assert_allclose(f, np.repeat(TABLE1["bending"], 2), rtol=5e-3)

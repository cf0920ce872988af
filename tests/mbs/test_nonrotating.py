"""The spinning linearisation in non-rotating bending coordinates (:mod:`ddgsa.mbs.nonrotating`)
about an operating point that is not an equilibrium.

An axisymmetric, undamped FE shaft on isotropic springs, loaded by a force fixed in space, has a
potential energy that does not depend on its spin angle (the elastic energy of a bending shape is
the same at every angle of the shaft, the force works on the displacement in space, which the
non-rotating coordinates ``xi`` are). With the bending rates zero in the non-rotating frame and
the spin steady, the spin equation's residual is zero whatever ``xi``: the spin rows of the
stiffness must vanish, ``K[spin, bending] = 0``. About a point where the bending coordinates are
off their equilibrium (a non-zero residual on them), that holds only when the projection
``T = dq/dz`` is taken at the perturbed state: with ``T`` frozen at the operating point the
residual's Galerkin term ``(dT/dz)^T r`` is lost and the spin rows get ``|r| x`` (shape) entries
(the defect that put a false 1x motor torque into the test rig's steady linear runs).
"""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import AppliedLoad, FlexibleBody, Ground, SpringDamper3, System
from ddgsa.mbs.beam import BeamSpec, mesh
from ddgsa.mbs.nonrotating import linearise

LENGTH, SPIN = 0.8, 150.0                                   # [m], [rad/s]
K_BEARING = 2e7                                             # [N/m]


def _shaft(load: tuple[float, float]) -> System:
    d, rho, e = 0.03, 7850.0, 2.1e11
    area, second = np.pi * d * d / 4, np.pi * d**4 / 64
    spec = BeamSpec(nodes=mesh([0.0, LENGTH], LENGTH / 10), mass=rho * area * LENGTH,
                    polar_inertia=rho * area * LENGTH * d * d / 8, EI=e * second, EA=e * area,
                    GJ=e / 2.6 * 2 * second,
                    end_masses=((0.0, 1e-9, 1e-9, 1e-9), (LENGTH / 2, 5.0, 0.02, 0.01)),
                    supports=(0.0, LENGTH), axial_support=0.0)
    shaft = FlexibleBody.shaft("shaft", spec, fields=("bending_y_1", "bending_z_1", "bending_y_2", "bending_z_2"),
                               angle_rates=(SPIN, 0.0, 0.0))
    ground = Ground()
    elements = [SpringDamper3(shaft.marker((x, 0.0, 0.0)), ground.marker((x, 0.0, 0.0)),
                              (K_BEARING if x == 0.0 else 0.0, K_BEARING, K_BEARING), name=f"bearing_{i}")
                for i, x in enumerate((0.0, LENGTH))]
    times = np.array([0.0, 1.0, 2.0])
    force = np.tile([0.0, *load], (3, 1))
    elements.append(AppliedLoad(shaft.marker((LENGTH / 2, 0.0, 0.0)), times, force=force, name="side_load"))
    return System([shaft], elements, gravity=(0.0, 0.0, -9.81))


@pytest.mark.parametrize("bent", [(0.0, 0.0), (3e-4, -2e-4)])
def test_spin_rows_vanish_about_a_point_off_equilibrium(bent):
    system = _shaft((120.0, -80.0))
    q0, qd0 = system.q0.copy(), system.qd0.copy()
    q0[system.index("shaft.rx")] = 0.7                       # any spin angle
    q0[system.index("shaft.bending_y_1")], q0[system.index("shaft.bending_z_1")] = bent
    lin = linearise(system, q0, qd0)
    isp = system.index("shaft.rx")
    bending = [system.index(f"shaft.bending_{a}_{k}") for k in (1, 2) for a in "yz"]
    assert np.abs(lin.r0[bending]).max() > 10.0              # off equilibrium: 120 N side load, gravity
    scale = np.abs(lin.k[np.ix_(bending, bending)]).max()
    assert np.abs(lin.k[isp, bending]).max() <= 1e-7 * scale, lin.k[isp, bending]


def _disk_on_light_shaft(spin: float) -> System:
    """A 20 kg disk (J_p 0.5, J_d 0.3 kg m^2) at mid-span of a light FE shaft on stiff bearings (the
    Jeffcott rotor of tests/mbs/test_campbell.py, its tilt here carried by the shaft's elastic modes)."""
    from ddgsa.mbs.bodies import bending_fields
    e, d = 211e9, 0.05
    spec = BeamSpec(nodes=mesh([0.0, 0.5, 1.0], 1.0 / 8), mass=1e-4, polar_inertia=1e-9, EI=e * np.pi * d**4 / 64,
                    EA=e * np.pi * d * d / 4, GJ=e / 2.6 * np.pi * d**4 / 32, end_masses=((0.5, 20.0, 0.5, 0.3),),
                    supports=(0.0, 1.0), axial_support=0.0)
    shaft = FlexibleBody.shaft("shaft", spec, fields=bending_fields(2), rotary_inertia=False,
                               angle_rates=(spin, 0.0, 0.0))
    ground = Ground()
    return System([shaft], [SpringDamper3(shaft.marker((x, 0.0, 0.0)), ground.marker((x, 0.0, 0.0)),
                                          (1e9 if x == 0.0 else 0.0, 1e9, 1e9), name=f"bearing_{i}")
                            for i, x in enumerate((0.0, 1.0))])


@pytest.mark.parametrize("spin", [200.0, 500.0])
def test_disk_whirl_with_spin_stiffening_matches_the_closed_form(spin):
    """Backward and forward tilt whirl of the disk, ``J_d w^2 -+ J_p W w - k_t = 0``, within 1e-5 (the shaft weighs 0.1 g) with
    the spin stiffening (the tilt stiffness ``k_t`` of mid-span on the pinned shaft and bearings, as in
    test_campbell's closed form); without it the tilt frequencies are low by the missing ``J_p / 2 W^2``
    (0.7 % backward at 200 rad/s, 5 % at 500)."""
    from ddgsa.mbs.modal import damped_eigen

    system = _disk_on_light_shaft(spin)
    keep = [i for i, nm in enumerate(system.coord_names) if not nm.endswith((".rx", ".x"))]
    sub = np.ix_(keep, keep)
    ei = 211e9 * np.pi * 0.05**4 / 64
    k_lat, k_tilt = 1 / (1 / (48 * ei) + 1 / 2e9), 1 / (1 / (12 * ei) + 2 / 1e9)
    root = np.sqrt((0.5 * spin) ** 2 + 4 * 0.3 * k_tilt)
    lateral, backward, forward = (np.sqrt(k_lat / 20.0) / (2 * np.pi), (root - 0.5 * spin) / 0.6 / (2 * np.pi),
                                  (root + 0.5 * spin) / 0.6 / (2 * np.pi))
    for stiffening in (True, False):
        lin = linearise(system, system.q0, system.qd0, spin_stiffening=stiffening)
        lam, _ = damped_eigen(lin.m[sub], lin.c[sub], lin.k[sub])
        f = np.abs(lam[:4]) / (2 * np.pi)
        np.testing.assert_allclose(f[:2], lateral, rtol=1e-5)
        if stiffening:
            np.testing.assert_allclose(f[2:], [backward, forward], rtol=1e-5)
        else:
            assert f[2] / backward - 1 < -(0.006 if spin < 300 else 0.04)


def test_inputs_of_a_load_outside_the_system_are_the_unbalance_in_closed_form():
    """An unbalance (5 g at 0.1 m) on the disk of the light shaft, an element on the system's marker but not
    among its parts (the test rig's block path projects its turning loads so): along one revolution at
    ``W = 200 rad/s`` its input on the shaft's lateral translations is the centrifugal force
    ``m e W^2 (cos W t, sin W t)`` [N] in the frame (the system's ``r0`` holds none of it); ``relative=True``
    gives its change since ``t0``."""
    from ddgsa.mbs import EccentricMass
    from ddgsa.mbs.nonrotating import projected_inputs

    spin, mass, radius = 200.0, 0.005, 0.1
    system = _disk_on_light_shaft(spin)
    disk = system.bodies[0].marker((0.5, 0.0, 0.0))
    system = System(system.bodies, [*system.elements, EccentricMass(disk, 0.0, radius)])   # the marker in the system
    lin = linearise(system, system.q0, system.qd0)
    t = np.linspace(0.0, 2 * np.pi / spin, 9)[:-1]
    load = [EccentricMass(disk, mass, radius)]
    absolute = projected_inputs(system, lin, t, load, relative=False)
    lateral = [system.index("shaft.y"), system.index("shaft.z")]
    want = mass * radius * spin**2 * np.column_stack([np.cos(spin * t), np.sin(spin * t)])
    np.testing.assert_allclose(absolute[:, lateral], want, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(projected_inputs(system, lin, t, load)[:, lateral], want - want[0], atol=1e-12)


def test_every_column_from_the_tangents_takes_no_residual_call(monkeypatch: pytest.MonkeyPatch) -> None:
    """``tangent_columns`` naming every coordinate: ``K`` and ``C`` are the parts' tangents alone, with no residual
    difference taken (the rig's sag at rest, docs/kernel.md). The translations' columns then agree with the central
    differences within 1e-6 of their largest entry, while the bending columns of the spinning shaft, whose
    centrifugal and Coriolis terms the tangents leave out, do not (the softening, 5.4e-5 of the column in ``K``,
    and more than half of ``C``)."""
    from ddgsa.mbs import nonrotating

    system = _shaft((120.0, -80.0))
    q0, qd0 = system.q0.copy(), system.qd0.copy()
    full = linearise(system, q0, qd0)

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("a residual difference was taken")

    monkeypatch.setattr(nonrotating, "_hybrid_jacobian", refuse)
    monkeypatch.setattr(nonrotating, "central_jacobian", refuse)
    tangent = linearise(system, q0, qd0, tangent_columns=range(system.n))
    for c in (system.index(f"shaft.{a}") for a in "xyz"):
        for got, want in ((tangent.k, full.k), (tangent.c, full.c)):
            assert np.abs(got[:, c] - want[:, c]).max() <= 1e-6 * np.abs(want[:, c]).max()
    bend = system.index("shaft.bending_y_1")
    assert np.abs(tangent.k[:, bend] - full.k[:, bend]).max() > 1e-5 * np.abs(full.k[:, bend]).max()
    assert np.abs(tangent.c[:, bend] - full.c[:, bend]).max() > 0.5 * np.abs(full.c[:, bend]).max()


@pytest.mark.parametrize("spin", [200.0, 500.0])
def test_exact_damping_at_speed_gives_the_closed_form_whirl(spin: float) -> None:
    """``damping_tangents`` at speed (``C`` from the tangents, the bodies' exact rate slopes and the map's rate
    terms, no residual call for it): the disk's backward and forward tilt whirl ``J_d w^2 -+ J_p W w - k_t = 0``
    within 1e-5, as the central differences give it (the gyroscopic ``J_p W`` is the whole of the split)."""
    from ddgsa.mbs.compiled import compile_terms
    from ddgsa.mbs.modal import damped_eigen

    system = _disk_on_light_shaft(spin)
    assert compile_terms(system)
    keep = [i for i, nm in enumerate(system.coord_names) if not nm.endswith((".rx", ".x"))]
    sub = np.ix_(keep, keep)
    k_tilt = 1 / (1 / (12 * 211e9 * np.pi * 0.05**4 / 64) + 2 / 1e9)
    root = np.sqrt((0.5 * spin) ** 2 + 4 * 0.3 * k_tilt)
    whirl = np.array([root - 0.5 * spin, root + 0.5 * spin]) / 0.6 / (2 * np.pi)
    lin = linearise(system, system.q0, system.qd0, spin_stiffening=True, damping_tangents=True)
    lam, _ = damped_eigen(lin.m[sub], lin.c[sub], lin.k[sub])
    np.testing.assert_allclose(np.abs(lam[2:4]) / (2 * np.pi), whirl, rtol=1e-5)


def test_exact_damping_at_speed_refuses_a_turning_eccentric_mass() -> None:
    """An eccentric mass's force ``m e W^2`` changes with the spin rate but gives no damping tangent, so the
    tangents' ``C`` would miss its column: ``damping_tangents`` at speed refuses it (where the differences show
    that column nonzero), and takes it at rest, where the slope is zero, or with the mass at zero."""
    from ddgsa.errors import ModelError
    from ddgsa.mbs.compiled import compile_terms
    from ddgsa.mbs.elements import EccentricMass

    plain = _disk_on_light_shaft(300.0)
    shaft = plain.bodies[0]
    system = System(plain.bodies, [*plain.elements, EccentricMass(shaft.marker((0.5, 0.0, 0.0)), 0.01, 0.1)])
    assert compile_terms(system)
    spin = system.index("shaft.rx")
    light = System(plain.bodies, [*plain.elements, EccentricMass(shaft.marker((0.5, 0.0, 0.0)), 0.0, 0.1)])
    assert compile_terms(light)
    full, none = (linearise(s, s.q0, s.qd0, rel_step=1e-3) for s in (system, light))
    slope = np.abs(full.c[:, spin] - none.c[:, spin]).max()         # the slope the tangents would leave out:
    assert slope > 0.5 * 2 * 0.01 * 0.1 * 300.0                     # 2 m e W on the disk's lateral rows
    with pytest.raises(ModelError, match="rate slope of unbalance"):
        linearise(system, system.q0, system.qd0, damping_tangents=True)
    linearise(system, system.q0, np.zeros(system.n), damping_tangents=True)     # at rest: no slope
    linearise(light, light.q0, light.qd0, damping_tangents=True)


def test_exact_damping_at_speed_is_the_residuals_differences(monkeypatch: pytest.MonkeyPatch) -> None:
    """On the spinning shaft with damped bearings, a disk and a side load (off equilibrium), tilted and bent: every
    column of ``damping_tangents``' ``C`` agrees with central differences of the residual over the rates within
    1e-7 of its largest entry (the residual is quadratic in the rates, so the differences at a 1e-3 step are
    exact but for round-off: measured 1.7e-9 on the spin column on one CPU, 1.75e-8 on another -- the round-off
    of residuals of order 1e3 over a column of 0.09 -- and 2e-12 on the largest), with no residual call taken for it; the tangents alone (``T^T C_t T``) miss the
    gyroscopic and Coriolis columns by more than half. A spinning system without compiled terms is refused."""
    from ddgsa.errors import ModelError
    from ddgsa.mbs import nonrotating
    from ddgsa.mbs.compiled import compile_terms

    plain = _shaft((120.0, -80.0))
    elements = [SpringDamper3(el.markers[0], el.markers[1], (K_BEARING, K_BEARING, K_BEARING), (300.0, 500.0, 700.0),
                              name=el.name) if isinstance(el, SpringDamper3) else el for el in plain.elements]
    system = System(plain.bodies, elements, gravity=(0.0, 0.0, -9.81))
    q0, qd0 = system.q0.copy(), system.qd0.copy()
    q0[system.index("shaft.rx")] = 0.7
    q0[system.index("shaft.ry")], q0[system.index("shaft.bending_y_1")] = 2e-3, 3e-4
    qd0[system.index("shaft.rz")] = 0.5                      # a slow yaw rate besides the spin
    with pytest.raises(ModelError, match="compiled terms"):
        linearise(system, q0, qd0, damping_tangents=True)
    assert compile_terms(system)
    full = linearise(system, q0, qd0, rel_step=1e-3)
    calls: list[int] = []
    real = nonrotating._hybrid_jacobian
    monkeypatch.setattr(nonrotating, "_hybrid_jacobian", lambda *a: calls.append(a[2]) or real(*a))
    fast = linearise(system, q0, qd0, rel_step=1e-3, damping_tangents=True)
    assert calls == [0]                                       # K differenced, C not
    scale = np.abs(full.c).max(axis=0)
    assert np.all(np.abs(fast.c - full.c).max(axis=0) <= 1e-7 * scale), np.abs(fast.c - full.c).max(axis=0) / scale
    assert np.array_equal(fast.k, full.k)
    bend = system.index("shaft.bending_y_1")
    tangents = linearise(system, q0, qd0, tangent_columns=range(system.n))
    assert np.abs(tangents.c[:, bend] - full.c[:, bend]).max() > 0.5 * scale[bend]

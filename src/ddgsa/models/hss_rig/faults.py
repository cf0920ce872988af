"""Coupling misalignment for the linear fidelity: the turning anisotropy on the fixed offset as an external load.

The coupling (:class:`~ddgsa.models.hss_rig.elements.MisalignedCoupling`) is a 6-DOF bushing whose
lateral and angular stiffness pairs differ by ``+-a`` in the frame of the motor-side hub, which
turns at the shaft angle ``theta``; in the global frame its stiffness is
``K(theta) = B(theta) K_hub B(theta)^T = K_mean + dK(theta)``, ``dK`` made of ``cos 2 theta`` and
``sin 2 theta`` (a two-fold symmetry). Its force on the hub is ``K(theta) (d + delta)``, ``d`` the
relative motion of the shaft end and ``delta`` the fixed misalignment (parallel offset along
global y, angle about global z). The standard linear treatment (e.g. Sekhar & Prabhu, JSV 185
(1995); Friswell et al., *Dynamics of Rotating Machines* §5.7 for the parametric terms):

- ``K_mean (d + delta)`` stays in the time-invariant rig (the mean coupling and its static pull);
- ``dK(theta) s_0`` with ``s_0 = d_0 + delta`` the static stretch of the coupling at the spinning
  operating point (offset plus the static deflection it and gravity cause,
  :func:`operating_stretch`) is an **external** load at twice the shaft speed on the hub and,
  reversed, on the shaft end;
- the parametric term ``dK(theta) (d - d_0)``, the anisotropy acting on the shaft's vibration, is
  dropped: it is small when the vibration is small against the stretch (:func:`check_small`
  refuses a point where it is not).

The 1x part a real misaligned coupling also shows (from the offset's lever arm or a skewed hub) is
not modelled: the anisotropy gives even orders only.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs import AppliedLoad, Marker, nonrotating
from ddgsa.mbs.elements import Element
from ddgsa.models.hss_rig.elements import MisalignedCoupling
from ddgsa.models.hss_rig.rig import Rig

Array = NDArray[np.float64]

MAX_VIBRATION_RATIO = 0.2
"""Largest ratio of the coupling's vibration amplitude to its static stretch the linear treatment accepts [-]."""


def misaligned(p: Mapping[str, float]) -> bool:
    """Whether ``p`` has a coupling misalignment (parallel or angular)."""
    return bool(p["misalignment_parallel"] or p["misalignment_angular"])


def coupling_stretch(rig: Rig, q: Array) -> Array:
    """The coupling's stretch ``d + delta`` (6,) [m, rad] in the global frame at the rig's state ``q``."""
    system = rig.system
    coupling = next(e for e in system.elements if isinstance(e, MisalignedCoupling))
    states = [system.marker_state(m, q, np.zeros_like(q), 0.0) for m in coupling.markers]
    return coupling._deflection(states)[0]


def operating_stretch(rig: Rig, q0: Array, qd0: Array, iterations: int = 8, rtol: float = 1e-3) -> Array:
    """The coupling's static stretch ``s_0`` (6,) at the spinning rig's operating point.

    Newton's method on the steady spinning rig from ``(q0, qd0)`` (the rig at rest's sag): each
    step the static part of the rig linearised in non-rotating coordinates
    (:func:`ddgsa.mbs.nonrotating.linearise`; least squares: the spin angle carries none), until
    the residual falls by ``rtol`` (its finite-difference tangent stalls near 1e-4). One step is
    not enough: the transmitted torque twists the coupling across the offset (at the nominal
    values the first step's angular stretch is off by its whole size; three steps agree with
    the mean of a nonlinear ``kloss`` run to 0.5 %)."""
    q, first = q0, None
    for _ in range(iterations):
        lin = nonrotating.linearise(rig.system, q, qd0)
        size = float(np.linalg.norm(lin.r0))
        first = size if first is None else first
        if size <= rtol * first:
            break
        z0 = np.linalg.lstsq(lin.k, lin.r0, rcond=nonrotating.RIGID_RCOND)[0]
        zero = np.zeros_like(z0)
        q = lin.state(z0, zero, zero, lin.t0)[0]
    else:
        raise ModelError(f"model 'hss_rig': the steady operating point with the misalignment did not converge in "
                         f"{iterations} Newton steps (residual {size:.3g} of {first:.3g})")
    return coupling_stretch(rig, q)


def anisotropy(p: Mapping[str, float], theta: float) -> Array:
    """``dK(theta) = B K_hub B^T - K_mean`` (6, 6) [N/m, N m/rad] of the coupling at hub angle ``theta`` [rad]."""
    a = p["coupling_asymmetry"]
    kr, ka = p["coupling_radial_stiffness"], p["coupling_angular_stiffness"]
    dk_hub = np.diag([0.0, a * kr, -a * kr, 0.0, a * ka, -a * ka])
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])        # the hub frame: a turn about x
    big = np.zeros((6, 6))
    big[:3, :3] = big[3:, 3:] = rot
    return big @ dk_hub @ big.T


def misalignment_loads(p: Mapping[str, float], stretch: Array, spin: float, duration: float,
                       step: float) -> Callable[[dict[str, Marker]], list[Element]]:
    """``extra`` for :func:`~ddgsa.models.hss_rig.rig.build`: the loads ``+-dK(spin t) stretch`` on the
    hub and the shaft end (the markers coincide, so no couple), sampled every ``step`` [s] to
    ``duration`` [s] plus two samples (see the module)."""
    t = step * np.arange(int(round(duration / step)) + 3)
    wrench = np.array([anisotropy(p, spin * ti) @ stretch for ti in t])

    def loads(markers: dict[str, Marker]) -> list[Element]:
        return [AppliedLoad(markers["hub"], t, wrench[:, :3], wrench[:, 3:], name="misalignment_hub"),
                AppliedLoad(markers["coupling"], t, -wrench[:, :3], -wrench[:, 3:], name="misalignment_shaft")]
    return loads


def check_small(p: Mapping[str, float], rig: Rig, q: Array) -> None:
    """Refuse a record whose coupling vibration is not small against the static stretch.

    The dropped parametric term is ``dK (d - d_0)``; against the kept ``dK s_0`` it is the ratio of
    the lateral (angular) vibration amplitude to the stretch, checked where a parallel (angular)
    misalignment is given. Above :data:`MAX_VIBRATION_RATIO` the
    linear treatment is not the rig's answer: use ``kloss``.

    Parameters
    ----------
    p : mapping
        The parameters (the misalignments).
    q : (n_t, n)
        The record's coordinates.
    """
    d = np.array([coupling_stretch(rig, qi) for qi in q[:: max(1, q.shape[0] // 64)]])
    stretch = d.mean(axis=0)                       # the record's mean: the static stretch
    for idx, what, given in (((1, 2), "lateral [m]", p["misalignment_parallel"]),
                             ((4, 5), "angular [rad]", p["misalignment_angular"])):
        if not given:
            continue
        s0 = float(np.hypot(*stretch[list(idx)]))
        vib = float(np.max(np.hypot(*(d[:, list(idx)] - d[:, list(idx)].mean(axis=0)).T)))
        if s0 > 0.0 and vib > MAX_VIBRATION_RATIO * s0:
            raise ModelError(f"model 'hss_rig': fidelity 'linear' carries a misalignment as an external load only "
                             f"while the coupling's vibration is small against its static stretch; here the "
                             f"{what} vibration {vib:.3g} exceeds {MAX_VIBRATION_RATIO:g} x the stretch {s0:.3g}; "
                             "use 'kloss' or 'dq'")

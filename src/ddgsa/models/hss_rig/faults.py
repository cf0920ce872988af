"""The coupling's turning anisotropy for the linear fidelity: its action on the static stretch as an external load.

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
  operating point (:func:`operating_stretch`) is an **external** load at twice the shaft speed on
  the hub and, reversed, on the shaft end. The stretch is not the offset alone: the disk's gravity
  sag tilts the shaft at bearing 1 and lifts its overhang against the hub, and the transmitted
  torque twists the coupling across both (0.14 mm vertical at the nominal values, aligned), so
  the healthy rig has a 2x too;
- the parametric term ``dK(theta) (d - d_0)``, the anisotropy acting on the shaft's vibration, is
  dropped. It moves a 1x vibration to 1x and 3x and a 2x one to 0x and 4x, so it changes the 2x
  orders only at second order, by about the ratio of the coupling's 2x vibration to its stretch;
  :func:`check_small` refuses a record where that ratio is not small (near a parametric
  resonance, where the time-invariant rig is not the answer).

The 1x part a real misaligned coupling also shows (from the offset's lever arm or a skewed hub) is
not modelled: the anisotropy gives even orders only.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs import AppliedLoad, Marker, nonrotating
from ddgsa.mbs.compiled import HybridTerms
from ddgsa.mbs.elements import Element
from ddgsa.models.hss_rig.elements import MisalignedCoupling
from ddgsa.models.hss_rig.rig import Rig

Array = NDArray[np.float64]

MAX_VIBRATION_RATIO = 0.2
"""Largest ratio of the coupling's 2x vibration amplitude to its static stretch the linear treatment accepts [-]."""
CHECK_SAMPLES = 64
"""About how many samples of a record :func:`check_small` fits its mean, 1x, 2x and 3x to (7 unknowns; a
steady record's samples fall at scattered shaft angles, so a few dozen fix them)."""


def misaligned(p: Mapping[str, float]) -> bool:
    """Whether ``p`` has a coupling misalignment (parallel or angular)."""
    return bool(p["misalignment_parallel"] or p["misalignment_angular"])


def coupling_of(rig: Rig) -> MisalignedCoupling:
    """The rig's coupling element."""
    return next(e for e in rig.system.elements if isinstance(e, MisalignedCoupling))


def coupling_stretch(rig: Rig, q: Array, coupling: MisalignedCoupling | None = None) -> Array:
    """The coupling's stretch ``d + delta`` (6,) [m, rad] in the global frame at the rig's state ``q``
    (``coupling``: the rig's coupling element, :func:`coupling_of`, when the caller has it)."""
    system = rig.system
    coupling = coupling_of(rig) if coupling is None else coupling
    states = system.states_of(coupling.markers, q, np.zeros_like(q), 0.0)
    return coupling._deflection(states)[0]


def coupling_stretches(rig: Rig, q: Array, coupling: MisalignedCoupling) -> Array:
    """:func:`coupling_stretch` (n_t, 6) at each row of ``q`` (n_t, n): the coupling's markers from the kernel's
    tables of those markers alone (``HybridTerms.states_along``: the same states, bit for bit) where the rig's
    terms are compiled."""
    system = rig.system
    zero = np.zeros_like(q)
    if isinstance(system.fast_terms, HybridTerms) and all(system.fast_terms.has(m) for m in coupling.markers):
        states = system.fast_terms.states_along(coupling.markers, q, zero, np.zeros(len(q)))
    else:
        states = [system.states_of(coupling.markers, qi, zi, 0.0) for qi, zi in zip(q, zero)]
    return np.array([coupling._deflection(st)[0] for st in states])


def operating_stretch(rig: Rig, q0: Array, qd0: Array, iterations: int = 8, rtol: float = 1e-4,
                      tangent: Array | None = None, start: nonrotating.SpinLinearisation | None = None) -> Array:
    """The coupling's static stretch ``s_0`` (6,) at the spinning rig's operating point.

    Newton's method on the steady spinning rig from ``(q0, qd0)`` (the rig at rest's sag): each
    step the static part of the rig linearised in non-rotating coordinates
    (:func:`ddgsa.mbs.nonrotating.linearise`; least squares: the spin angle carries none), until
    the stretch changes by less than ``rtol`` of its size (the residual itself stalls near 1e-3
    of its start with the finite-difference tangent). One step is not enough: the transmitted
    torque twists the coupling across the stretch (at the nominal values the first step's
    angular stretch is off by its whole size; from the second step on the stretch agrees with the
    mean of a nonlinear ``kloss`` run to 0.5 %).

    With ``tangent`` (n, n) given (a stiffness of the same rig the caller has, e.g. of its full
    linearisation) the steps keep it (a chord method): one evaluation of the residual a step
    instead of a linearisation, more steps (``iterations`` is then at least 30) to the same point.
    ``start``: the rig linearised at ``(q0, qd0)`` (:func:`ddgsa.mbs.nonrotating.linearise`, ``t0 = 0``) where the
    caller has it, with ``tangent``: the first step takes its residual and map instead of evaluating them again.
    """
    if start is not None and (tangent is None or start.t0 != 0.0 or not np.array_equal(start.q0, q0)
                              or not np.array_equal(start.qd0, qd0)):
        raise ValueError("operating_stretch: start must be the rig linearised at (q0, qd0), t0 = 0, with a tangent given")
    q, last = q0, None
    steps = iterations if tangent is None else max(iterations, 30)
    # the chord's least squares on its one tangent, factored once (the same minimum-norm solution and cut-off)
    chord = None if tangent is None else np.linalg.pinv(tangent, rcond=nonrotating.RIGID_RCOND)
    for step in range(steps):
        lin = start if step == 0 and start is not None else nonrotating.linearise(
            rig.system, q, qd0, static=True, residual_only=tangent is not None)
        z0 = np.linalg.lstsq(lin.k, lin.r0, rcond=nonrotating.RIGID_RCOND)[0] if chord is None else chord @ lin.r0
        zero = np.zeros_like(z0)
        q = lin.state(z0, zero, zero, lin.t0)[0]
        stretch = coupling_stretch(rig, q)
        if last is not None and np.linalg.norm(stretch - last) <= rtol * np.linalg.norm(stretch):
            return stretch
        last = stretch
    raise ModelError(f"model 'hss_rig': the coupling's static stretch at the operating point did not settle in "
                     f"{steps} Newton steps (last change {np.linalg.norm(stretch - last):.3g} of "
                     f"{np.linalg.norm(stretch):.3g})")


def anisotropy(p: Mapping[str, float], theta: float) -> Array:
    """``dK(theta) = B K_hub B^T - K_mean`` (6, 6) [N/m, N m/rad] of the coupling at hub angle ``theta`` [rad]."""
    return anisotropy_matrix(anisotropy_constants(p), float(theta))


def anisotropy_constants(p: Mapping[str, float]) -> tuple[float, float]:
    """``(a k_r, a k_a)`` [N/m, N m/rad]: the coupling's radial and angular stiffness times its
    asymmetry ``a``, what :func:`anisotropy_matrix` reads."""
    a = p["coupling_asymmetry"]
    return float(a * p["coupling_radial_stiffness"]), float(a * p["coupling_angular_stiffness"])


@njit(cache=True)
def anisotropy_matrix(stiffness, theta):  # pragma: no cover (compiled)
    """:func:`anisotropy` from :func:`anisotropy_constants` ``stiffness``."""
    # B diag(0, a k, -a k) B^T for B the hub frame's turn about x: a k [[cos 2t, sin 2t], [sin 2t, -cos 2t]]
    c2, s2 = math.cos(2 * theta), math.sin(2 * theta)
    out = np.zeros((6, 6))
    for lo, k in ((1, stiffness[0]), (4, stiffness[1])):
        out[lo, lo], out[lo, lo + 1], out[lo + 1, lo], out[lo + 1, lo + 1] = k * c2, k * s2, k * s2, -k * c2
    return out


@njit(cache=True)
def _turning_wrench(stiffness, theta, stretch):  # pragma: no cover (compiled)
    """``anisotropy_matrix(stiffness, theta_i) @ stretch`` (n_t, 6) for the hub angles ``theta`` (n_t,)."""
    out = np.empty((theta.size, 6))
    for i in range(theta.size):
        out[i] = anisotropy_matrix(stiffness, theta[i]) @ stretch
    return out


def anisotropy_loads(p: Mapping[str, float], stretch: Array, spin: float, duration: float,
                       step: float) -> Callable[[dict[str, Marker]], list[Element]]:
    """``extra`` for :func:`~ddgsa.models.hss_rig.rig.build`: the loads ``+-dK(spin t) stretch`` on the
    hub and the shaft end (the markers coincide, so no couple), sampled every ``step`` [s] to
    ``duration`` [s] plus two samples (see the module)."""
    t = step * np.arange(int(round(duration / step)) + 3)
    wrench = _turning_wrench(anisotropy_constants(p), spin * t, np.asarray(stretch, dtype=float))

    def loads(markers: dict[str, Marker]) -> list[Element]:
        return [AppliedLoad(markers["hub"], t, wrench[:, :3], wrench[:, 3:], name="anisotropy_hub"),
                AppliedLoad(markers["coupling"], t, -wrench[:, :3], -wrench[:, 3:], name="anisotropy_shaft")]
    return loads


def mean_and_2x(x: Array, angle: Array) -> tuple[Array, Array]:
    """Mean ``(m,)`` and 2x cosine/sine amplitudes ``(2, m)`` of the columns of ``x`` ``(n, m)``
    against the shaft ``angle`` ``(n,)`` [rad].

    The 1x and 3x parts are fitted with them (least squares): a large 1x orbit, such as an
    unbalance response near the critical speed, would otherwise leak into the 2x estimate of a
    record that is no whole number of revolutions.
    """
    basis = np.column_stack([np.ones_like(angle)] + [f(k * angle) for k in (1, 2, 3) for f in (np.cos, np.sin)])
    coef = np.linalg.lstsq(basis, x, rcond=None)[0]
    return coef[0], coef[3:5]


def check_small(rig: Rig, q: Array, t: Array, spin: float) -> None:
    """Refuse a record whose coupling vibrates at 2x by more than :data:`MAX_VIBRATION_RATIO` of its stretch.

    The dropped parametric term ``dK (d - d_0)`` feeds back into the 2x orders through the 2x
    vibration of the coupling; against the kept ``dK s_0`` its size is the ratio of that vibration
    to the static stretch ``s_0`` (the record's mean), for the lateral and the angular pair. Above
    :data:`MAX_VIBRATION_RATIO` the linear treatment is not the rig's answer: use ``kloss``.

    Parameters
    ----------
    q : (n_t, n)
        The record's coordinates.
    t : (n_t,)
        Its times [s].
    spin : float
        The steady shaft speed [rad/s].
    """
    every = max(1, q.shape[0] // CHECK_SAMPLES)
    coupling = coupling_of(rig)
    d = coupling_stretches(rig, q[::every], coupling)
    mean, twice = mean_and_2x(d, spin * t[::every])
    for idx, what in (((1, 2), "lateral [m]"), ((4, 5), "angular [rad]")):
        cols = list(idx)
        s0 = float(np.hypot(*mean[cols]))
        vib = float(np.sqrt(np.sum(twice[:, cols] ** 2)))
        if vib > MAX_VIBRATION_RATIO * s0:
            raise ModelError(f"model 'hss_rig': fidelity 'linear' carries the coupling's anisotropy as an external 2x "
                             f"load only while the coupling's 2x vibration is small against its static stretch; here "
                             f"the {what} 2x vibration {vib:.3g} exceeds {MAX_VIBRATION_RATIO:g} x the stretch "
                             f"{s0:.3g} (near a parametric resonance); use 'kloss' or 'dq'")

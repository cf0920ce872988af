"""An induction machine's steady air-gap torque as a kernel part: compiled, written once.

The steady state of the fifth-order (dq) induction machine at a constant rotor speed, from its
per-phase equivalent circuit and a supply that may be unbalanced, ramped or cut (the physics and
its sources: :mod:`ddgsa.models.hss_rig.motor`). The functions read one flat array of
:data:`N_CONSTANTS` numbers (the layout below, built by
:func:`ddgsa.models.hss_rig.motor.machine_constants`), so that :meth:`TorqueLaw.machine
<ddgsa.mbs.elements.TorqueLaw.machine>` can store them as a compiled element's parameters and the
packed system run them with the rest of its elements; the Python API of the motor calls the same
functions.

Layout: ``[R_s, R_r, L_s, L_r, L_m, p, u, w_1, v_peak, t_ramp, w_0, floor, cut]`` -- stator and rotor
resistance [Ohm], stator, rotor and magnetising inductance [H], pole pairs, supply unbalance
(negative / positive sequence) [-], rated electrical frequency [rad/s], rated peak phase voltage
[V], frequency-ramp time [s] (0: direct-on-line), ramp start frequency [rad/s], voltage floor of a
ramp [-], and 1.0 where the supply is cut at ``t = 0`` (a coast-down), else 0.0.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from numba import njit

from ddgsa.mbs.derivatives import central_step

N_CONSTANTS = 13
"""Length of a machine's constants array (see the module)."""


@njit(cache=True)
def circuit_phasors(c, omega, rotor_speed, voltage):  # pragma: no cover (compiled)
    """Steady space-vector amplitudes ``(i_s, i_r, psi_s, psi_r)`` for a voltage ``voltage e^{j omega t}``
    [V] at electrical frequency ``omega`` [rad/s] and rotor speed ``rotor_speed`` [rad/s]: the dq
    equations in the stationary frame with ``d/dt = j omega`` (``v = R_s i_s + j omega psi_s``,
    ``0 = R_r i_r + j (omega - p w_m) psi_r``), by Cramer's rule."""
    rs, rr, ls, lr, lm, pole_pairs = c[0], c[1], c[2], c[3], c[4], c[5]
    w_slip = omega - pole_pairs * rotor_speed
    a = rs + 1j * omega * ls
    b = 1j * omega * lm
    cc = 1j * w_slip * lm
    d = rr + 1j * w_slip * lr
    det = a * d - b * cc
    i_s, i_r = voltage * d / det, -voltage * cc / det
    return i_s, i_r, ls * i_s + lm * i_r, lm * i_s + lr * i_r


@njit(cache=True)
def phasors_many(c, omega, rotor_speed, voltage, out):  # pragma: no cover (compiled)
    """:func:`circuit_phasors` elementwise into ``out`` (4, n)."""
    for j in range(omega.size):
        out[0, j], out[1, j], out[2, j], out[3, j] = circuit_phasors(c, omega[j], rotor_speed[j], voltage[j])


@njit(cache=True)
def steady_torque_terms(c, w, rotor_speed, v):  # pragma: no cover (compiled)
    """``(mean [N m], ripple [N m], phase [rad], current [A])`` of the steady torque
    ``mean + ripple cos(2 theta_e + phase)`` at electrical frequency ``w`` [rad/s], positive-sequence
    peak phase voltage ``v`` [V] and the machine's unbalance: ``T = 3/2 p Im(conj(psi_s) i_s)`` of
    the two sequence circuits (see :func:`ddgsa.models.hss_rig.motor.steady_torque`)."""
    k = 1.5 * c[5]
    unbalance = c[6]
    i1, _, psi1, _ = circuit_phasors(c, w, rotor_speed, v + 0j)
    mean = k * (psi1.conjugate() * i1).imag
    ripple = 0.0j
    if unbalance > 0:
        i2, _, psi2, _ = circuit_phasors(c, -w, rotor_speed, unbalance * v + 0j)
        mean += k * (psi2.conjugate() * i2).imag
        ripple = k * (psi2.conjugate() * i1 - psi1 * i2.conjugate())
    # Im(c e^{j x}) = |c| sin(x + arg c) = |c| cos(x + arg c - pi/2)
    return mean, abs(ripple), cmath.phase(ripple) - math.pi / 2, abs(i1)


@njit(cache=True)
def steady_torque_many(c, w, rotor_speed, v, out):  # pragma: no cover (compiled)
    """:func:`steady_torque_terms` elementwise into ``out`` (4, n)."""
    for j in range(w.size):
        out[0, j], out[1, j], out[2, j], out[3, j] = steady_torque_terms(c, w[j], rotor_speed[j], v[j])


@njit(cache=True)
def supply_state(c, t):  # pragma: no cover (compiled)
    """``(theta_e [rad], omega_e [rad/s], v_peak [V])`` of the positive sequence at ``t`` [s]:
    direct-on-line, or a frequency ramp at constant V/f with a voltage floor (the supply's own state;
    :func:`supply_on` adds the cut)."""
    w1, v_peak, tr, w0, floor = c[7], c[8], c[9], c[10], c[11]
    if tr <= 0.0:
        return w1 * t, w1, v_peak
    if t < tr:
        w = w0 + (w1 - w0) * t / tr
        theta = w0 * t + 0.5 * (w1 - w0) * t * t / tr
    else:
        w = w1
        theta = 0.5 * (w0 + w1) * tr + w1 * (t - tr)
    return theta, w, v_peak * max(w / w1, floor)


@njit(cache=True)
def supply_on(c, t):  # pragma: no cover (compiled)
    """:func:`supply_state` with the voltage 0 for ``t > 0`` where the supply is cut."""
    theta, w, v = supply_state(c, t)
    return theta, w, 0.0 if (c[12] > 0.0 and t > 0.0) else v


@njit(cache=True)
def supply_many(c, t, out):  # pragma: no cover (compiled)
    """:func:`supply_on` elementwise into ``out`` (3, n)."""
    for j in range(t.size):
        out[0, j], out[1, j], out[2, j] = supply_on(c, t[j])


@njit(cache=True)
def induction_torque(c, t, speed):  # pragma: no cover (compiled)
    """Air-gap torque [N m] of the steady equivalent circuit at time ``t`` [s] and rotor ``speed``
    [rad/s]: the mean and twice-line-frequency ripple of :func:`steady_torque_terms` at the supply's
    instantaneous frequency and voltage (0 where the supply is off), no flux dynamics."""
    theta, w, v = supply_on(c, t)
    if v == 0.0 or w <= 0.0:
        return 0.0
    mean, ripple, phase, _ = steady_torque_terms(c, w, speed, v)
    return mean + ripple * math.cos(2 * theta + phase)


@njit(cache=True)
def induction_slope(c, t, speed):  # pragma: no cover (compiled)
    """``dT/dw`` [N m s/rad] of :func:`induction_torque` by a central difference of step
    ``1e-6 max(1, |w|)`` (as :meth:`TorqueLaw.wrench <ddgsa.mbs.elements.TorqueLaw.wrench>` takes it
    of a law without a slope)."""
    h = central_step(speed, 1.0, 1e-6)
    return (induction_torque(c, t, speed + h) - induction_torque(c, t, speed - h)) / (2 * h)


@njit(cache=True)
def torque_many(c, t, speed, out):  # pragma: no cover (compiled)
    """:func:`induction_torque` elementwise into ``out`` (n,)."""
    for j in range(t.size):
        out[j] = induction_torque(c, t[j], speed[j])


MU_0 = 4e-7 * math.pi
"""Vacuum permeability [H/m]."""

N_AIR_GAP = 7
"""Length of an air gap's constants array (:func:`air_gap_pull`)."""


@njit(cache=True)
def air_gap_pull(c, ey, ez):  # pragma: no cover (compiled)
    """Net magnetic pull ``(F_y, F_z)`` [N] of a surface-PM air gap on an eccentric rotor and its slope
    ``dF/de`` (2, 2) [N/m], for the eccentricity ``(ey, ez)`` [m]: the sector model (the physics and its
    sources: :mod:`ddgsa.models.electromagnetic`, whose Python API calls this function).

    ``c = [g, h_m / mu_r, k_C, B_r, alpha_p, R L beta, N]``: mechanical gap [m], magnet height over its
    recoil permeability [m], Carter's factor, remanence [T], pole-arc ratio, sector area [m^2] and the
    number of sectors ``N`` (centres at ``beta/2 + i beta``, ``beta = 2 pi / N``). Sector ``i``'s gap is
    ``g - e . n_i``, its flux density ``B_r h / (h + k_C gap)`` and its pull ``alpha_p B^2 / (2 mu_0)``
    times the area along ``n_i``. Raises ValueError where the eccentricity closes the gap.
    """
    g, hm, kc, br, alpha, area, n = c[0], c[1], c[2], c[3], c[4], c[5], int(c[6])
    if math.hypot(ey, ez) >= g:
        raise ValueError("the rotor's eccentricity closes the air gap")
    beta = 2 * math.pi / n
    force = np.zeros(2)
    slope = np.zeros((2, 2))
    for i in range(n):
        theta = beta / 2 + beta * i
        ny, nz = math.cos(theta), math.sin(theta)
        gap = g - (ey * ny + ez * nz)
        b = br * hm / (hm + kc * gap)
        p = alpha * b * b / (2 * MU_0) * area
        force[0] += p * ny
        force[1] += p * nz
        s = alpha * b * b * kc / (MU_0 * (hm + kc * gap)) * area      # -dp/dgap times the area
        slope[0, 0] += s * ny * ny
        slope[0, 1] += s * ny * nz
        slope[1, 1] += s * nz * nz
    slope[1, 0] = slope[0, 1]
    return force, slope


@njit(cache=True)
def dq_currents(c, psi):  # pragma: no cover (compiled)
    """Stator and rotor current space vectors ``(i_s, i_r)`` [A] from the fluxes
    ``psi = (psi_sd, psi_sq, psi_rd, psi_rq)`` [Wb]: the inverse of the inductance matrix."""
    ls, lr, lm = c[2], c[3], c[4]
    det = ls * lr - lm * lm
    psi_s = complex(psi[0], psi[1])
    psi_r = complex(psi[2], psi[3])
    return (lr * psi_s - lm * psi_r) / det, (ls * psi_r - lm * psi_s) / det


@njit(cache=True)
def dq_rates(c, t, psi, speed):  # pragma: no cover (compiled)
    """Rates of the four flux linkages [Wb/s] and the air-gap torque [N m] of the fifth-order (dq)
    induction machine at time ``t`` [s], fluxes ``psi = (psi_sd, psi_sq, psi_rd, psi_rq)`` [Wb] in the
    frame of the positive-sequence supply angle and mechanical rotor ``speed`` [rad/s]:
    ``psi_s' = v_s - R_s i_s - j w psi_s``, ``psi_r' = -R_r i_r - j (w - p w_m) psi_r``,
    ``T = 3/2 p Im(conj(psi_s) i_s)``, the currents :func:`dq_currents`, the supply from
    :func:`supply_on` (its unbalance a negative sequence; 0 V once cut). The rig's motor module
    (:func:`ddgsa.models.hss_rig.motor.dq_derivatives`) and its dq element call it."""
    rs, rr, pole_pairs, unbalance = c[0], c[1], c[5], c[6]
    theta, w, v = supply_on(c, t)
    v_s = v * (1.0 + unbalance * complex(math.cos(2 * theta), -math.sin(2 * theta)))
    psi_s = complex(psi[0], psi[1])
    psi_r = complex(psi[2], psi[3])
    i_s, i_r = dq_currents(c, psi)
    d_s = v_s - rs * i_s - 1j * w * psi_s
    d_r = -rr * i_r - 1j * (w - pole_pairs * speed) * psi_r
    rates = np.empty(4)
    rates[0], rates[1], rates[2], rates[3] = d_s.real, d_s.imag, d_r.real, d_r.imag
    return rates, 1.5 * pole_pairs * (psi_s.conjugate() * i_s).imag


@njit(cache=True)
def dq_wrench(c, t, a, w, v, i, j):  # pragma: no cover (compiled)
    """``(W (2, 6), C (12, 12))`` of a dq machine between the rotor marker ``i`` and the marker ``j`` of its
    flux states (their rates are marker j's velocity ``v[j]`` and angular velocity ``w[j][0]``): the
    torque :func:`dq_rates` about marker i's x axis and the flux rates on marker j, and ``C = -dW/d``
    (marker velocities) by central differences over the rotor's spin rate (step ``1e-6 max(1, |w_m|)``)
    and the four fluxes (step ``1e-7 max(1e-3, max |psi|)``)."""
    axis = a[i][:, 0].copy()
    speed = axis[0] * w[i][0] + axis[1] * w[i][1] + axis[2] * w[i][2]
    psi = np.array([v[j][0], v[j][1], v[j][2], w[j][0]])
    rates, torque = dq_rates(c, t, psi, speed)
    out = np.zeros((2, 6))
    out[0, 3:] = torque * axis
    out[1, :3] = rates[:3]
    out[1, 3] = rates[3]
    damping = np.zeros((12, 12))
    h_psi = central_step(np.max(np.abs(psi)), 1e-3, 1e-7)
    for col in range(5):                         # the rotor's spin, then the four fluxes
        if col == 0:
            h = central_step(speed, 1.0, 1e-6)
            dp, tp = dq_rates(c, t, psi, speed + h)
            dm, tm = dq_rates(c, t, psi, speed - h)
        else:
            h = h_psi
            step = np.zeros(4)
            step[col - 1] = h
            dp, tp = dq_rates(c, t, psi + step, speed)
            dm, tm = dq_rates(c, t, psi - step, speed)
        vec = np.zeros(12)
        vec[3:6] = (tp - tm) / (2 * h) * axis                  # torque on the rotor
        vec[6:10] = (dp - dm) / (2 * h)                        # flux rates
        if col == 0:
            for m in range(12):
                for n in range(3):
                    damping[m, 3 + n] = -vec[m] * axis[n]
        else:
            damping[:, 5 + col] = -vec
    return out, damping

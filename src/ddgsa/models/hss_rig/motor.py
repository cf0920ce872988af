"""Three-phase squirrel-cage induction motor of the test rig at two fidelities.

Both fidelities come from one per-phase equivalent circuit (stator ``R_s, L_ls``, magnetising
``L_m``, rotor referred to the stator ``R_r, L_lr``; ``p`` pole pairs; line-to-line RMS supply
``V`` at ``f``):

``dq``
    The fifth-order machine model (Krause, *Analysis of Electric Machinery*, 3rd ed., §6.5 and
    §6.10): four flux linkages plus the rotor speed, here written with complex space vectors in
    the frame that turns with the positive-sequence supply angle ``theta_e(t)`` (amplitude-
    invariant transform, peak values)::

        v_s = R_s i_s + d psi_s/dt + j w_e psi_s
        0   = R_r i_r + d psi_r/dt + j (w_e - p w_m) psi_r
        psi_s = L_s i_s + L_m i_r,  psi_r = L_m i_s + L_r i_r,  L_s = L_ls + L_m, L_r = L_lr + L_m
        T_e = 3/2 p Im(conj(psi_s) i_s)                                  [N m]

    The fifth state, the rotor speed ``w_m``, belongs to the mechanics (the rig's motor rotor);
    :func:`dq_derivatives` gives the four electrical rates and the torque for a given speed.
``kloss``
    The steady-state torque–slip curve of the same circuit
    (``T = 3 |I_r|^2 R_r / (s w_s)``, ``w_s = w_e / p``), i.e. the dq model with the flux
    transients removed. :func:`kloss_torque` is Kloss's classic two-parameter formula
    (breakdown torque and slip from the Thevenin equivalent), exact when ``R_s = 0`` and kept
    for the docs and tests; the rig uses the exact circuit curve.

Supply: direct-on-line at ``V, f`` or a frequency ramp at constant ``V/f`` (with a voltage floor,
the usual IR boost of a frequency converter). The motor-side fault is a **supply voltage
unbalance**: a negative-sequence voltage of ``u`` times the positive one (IEC 60034-26's
voltage unbalance factor). It brakes the rotor (the negative-sequence field runs at slip
``2 - s``) and makes a torque ripple at twice the supply frequency; :func:`steady_torque` gives
both in closed form from the two sequence circuits, and the ``dq`` model carries them by itself.
Broken rotor bars are not modelled (they need a rotor with per-bar asymmetry, not a dq circuit).

Default data (:data:`LAB_MOTOR`): Krause's 3-hp, 4-pole benchmark machine (op. cit. Table 6.10-1:
``r_s`` = 0.435 Ohm, ``X_ls = X'_lr`` = 0.754 Ohm, ``X_M`` = 26.13 Ohm, ``r'_r`` = 0.816 Ohm at
60 Hz, 220 V, rotor inertia 0.089 kg m^2), a lab-scale motor of the size a high-speed-shaft rig
uses; the reactances are turned into inductances at 60 Hz and the supply is moved to the 50 Hz
grid of the rig at the same volts per hertz (183.3 V), so the synchronous speed is 1500 rpm,
the high-speed-shaft speed of a geared wind turbine (seed 001 §1). This is an assumption: the
rig's own motor data (seed 001 paper A) are not available to us.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.machines import (circuit_phasors, dq_currents, dq_rates, phasors_many, steady_torque_many,
                                steady_torque_terms, supply_many, supply_state)


@dataclass(frozen=True)
class InductionMotor:
    """Equivalent-circuit data and supply of an induction motor (SI units, per phase, referred to the stator).

    Attributes
    ----------
    stator_resistance : float
        ``R_s`` [Ohm].
    rotor_resistance : float
        ``R_r`` [Ohm].
    stator_leakage_inductance : float
        ``L_ls`` [H].
    rotor_leakage_inductance : float
        ``L_lr`` [H].
    magnetising_inductance : float
        ``L_m`` [H].
    pole_pairs : int
        ``p`` [-].
    supply_voltage : float
        Rated line-to-line RMS voltage ``V`` [V].
    supply_frequency : float
        Rated supply frequency ``f`` [Hz].
    supply_unbalance : float
        Negative-sequence / positive-sequence voltage ratio ``u`` [-] (0: healthy).
    """

    stator_resistance: float = 0.435
    rotor_resistance: float = 0.816
    stator_leakage_inductance: float = 0.754 / (2 * math.pi * 60)
    rotor_leakage_inductance: float = 0.754 / (2 * math.pi * 60)
    magnetising_inductance: float = 26.13 / (2 * math.pi * 60)
    pole_pairs: int = 2
    supply_voltage: float = 220.0 * 50.0 / 60.0
    supply_frequency: float = 50.0
    supply_unbalance: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ModelError(f"induction motor field {f.name!r} must be a finite number, got {v!r}")
            if f.name == "supply_unbalance":
                if not 0.0 <= v < 1.0:
                    raise ModelError(f"induction motor field 'supply_unbalance' must be in [0, 1), got {v}")
            elif f.name == "stator_resistance":
                if v < 0:
                    raise ModelError(f"induction motor field 'stator_resistance' must be >= 0, got {v}")
            elif v <= 0:
                raise ModelError(f"induction motor field {f.name!r} must be > 0, got {v}")
        if int(self.pole_pairs) != self.pole_pairs:
            raise ModelError(f"induction motor field 'pole_pairs' must be an integer, got {self.pole_pairs}")

    def updated(self, values: dict[str, Any] | None) -> "InductionMotor":
        """A copy with the fields named in ``values`` replaced (other keys are ignored)."""
        names = {f.name for f in fields(self)}
        return replace(self, **{k: v for k, v in (values or {}).items() if k in names})

    @property
    def stator_inductance(self) -> float:
        """``L_s = L_ls + L_m`` [H]."""
        return self.stator_leakage_inductance + self.magnetising_inductance

    @property
    def rotor_inductance(self) -> float:
        """``L_r = L_lr + L_m`` [H]."""
        return self.rotor_leakage_inductance + self.magnetising_inductance

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed at the rated supply ``2 pi f / p`` [rad/s]."""
        return 2 * math.pi * self.supply_frequency / self.pole_pairs

    @property
    def phase_voltage_peak(self) -> float:
        """Peak phase voltage ``sqrt(2) V / sqrt(3)`` [V] (the amplitude of the voltage space vector)."""
        return math.sqrt(2.0 / 3.0) * self.supply_voltage


LAB_MOTOR = InductionMotor()
"""Krause's 3-hp 4-pole machine on a 50 Hz supply at the same V/Hz (see the module)."""


# -- steady state: the equivalent circuit -------------------------------------------------------
def rotor_current(motor: InductionMotor, slip: ArrayLike, frequency: float | None = None,
                  voltage: float | None = None) -> NDArray[np.complex128]:
    """RMS rotor current phasor ``I_r`` [A] of the per-phase equivalent circuit at ``slip`` [-].

    ``frequency`` [Hz] and ``voltage`` (line-to-line RMS) [V] default to the motor's rated supply.
    """
    s = np.asarray(slip, dtype=float)
    f = motor.supply_frequency if frequency is None else frequency
    v = (motor.supply_voltage if voltage is None else voltage) / math.sqrt(3.0)
    w = 2 * math.pi * f
    zs = motor.stator_resistance + 1j * w * motor.stator_leakage_inductance
    zm = 1j * w * motor.magnetising_inductance
    with np.errstate(divide="ignore", invalid="ignore"):
        zr = motor.rotor_resistance / s + 1j * w * motor.rotor_leakage_inductance
        i_s = v / (zs + zm * zr / (zm + zr))
        i_r = i_s * zm / (zm + zr)
    return np.where(s == 0.0, 0.0 + 0.0j, i_r)


def circuit_torque(motor: InductionMotor, slip: ArrayLike, frequency: float | None = None,
                   voltage: float | None = None) -> NDArray[np.float64]:
    """Air-gap torque ``3 |I_r|^2 R_r / (s w_s)`` [N m] of the equivalent circuit at ``slip`` [-].

    Positive slip motors, negative slip generates; zero at synchronous speed.

    Examples
    --------
    >>> round(float(circuit_torque(LAB_MOTOR, 0.0)), 6)
    0.0
    """
    s = np.asarray(slip, dtype=float)
    f = motor.supply_frequency if frequency is None else frequency
    w_sync = 2 * math.pi * f / motor.pole_pairs
    i_r = rotor_current(motor, s, f, voltage)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = 3.0 * np.abs(i_r) ** 2 * motor.rotor_resistance / (s * w_sync)
    return np.where(s == 0.0, 0.0, t)


def breakdown(motor: InductionMotor) -> tuple[float, float]:
    """Breakdown (pull-out) slip ``s_k`` [-] and torque ``T_k`` [N m] from the Thevenin equivalent.

    ``s_k = R_r / sqrt(R_th^2 + (X_th + X_lr)^2)``,
    ``T_k = 3 V_th^2 / (2 w_s (R_th + sqrt(R_th^2 + (X_th + X_lr)^2)))``
    (e.g. Chapman, *Electric Machinery Fundamentals*, eqs. 6-53 and 6-54).
    """
    w = 2 * math.pi * motor.supply_frequency
    zs = motor.stator_resistance + 1j * w * motor.stator_leakage_inductance
    zm = 1j * w * motor.magnetising_inductance
    v_ph = motor.supply_voltage / math.sqrt(3.0)
    v_th = abs(v_ph * zm / (zs + zm))
    z_th = zs * zm / (zs + zm)
    root = math.hypot(z_th.real, z_th.imag + w * motor.rotor_leakage_inductance)
    s_k = motor.rotor_resistance / root
    t_k = 3 * v_th**2 / (2 * motor.synchronous_speed * (z_th.real + root))
    return s_k, t_k


def kloss_torque(slip: ArrayLike, breakdown_slip: float, breakdown_torque: float) -> NDArray[np.float64]:
    """Kloss's formula ``T = 2 T_k / (s / s_k + s_k / s)`` [N m] (exact for ``R_s = 0``)."""
    s = np.asarray(slip, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = 2 * breakdown_torque / (s / breakdown_slip + breakdown_slip / s)
    return np.where(s == 0.0, 0.0, t)


# -- steady state of the dq model: two sequence circuits ----------------------------------------
def sequence_phasors(motor: InductionMotor, omega: float, rotor_speed: float,
                     voltage: complex) -> tuple[complex, complex, complex, complex]:
    """Steady space-vector amplitudes ``(i_s, i_r, psi_s, psi_r)`` for a voltage ``voltage e^{j omega t}``.

    Solves the dq equations in the stationary frame with ``d/dt = j omega``:
    ``v = R_s i_s + j omega psi_s``, ``0 = R_r i_r + j (omega - p w_m) psi_r``.

    Parameters
    ----------
    omega : float or array
        Electrical angular frequency of the voltage component [rad/s] (negative for the
        negative sequence).
    rotor_speed : float or array
        Mechanical rotor speed ``w_m`` [rad/s].
    voltage : complex or array
        Complex amplitude of the voltage space vector [V] (peak phase voltage).
    """
    if np.ndim(omega) or np.ndim(rotor_speed) or np.ndim(voltage):     # a record: elementwise
        omega, rotor_speed, voltage = np.broadcast_arrays(omega, rotor_speed, voltage)
        out = np.empty((4,) + omega.shape, dtype=complex)
        phasors_many(machine_constants(motor), omega.ravel().astype(float), rotor_speed.ravel().astype(float),
                     voltage.ravel().astype(complex), out.reshape(4, -1))
        return out[0], out[1], out[2], out[3]
    return circuit_phasors(machine_constants(motor), float(omega), float(rotor_speed), complex(voltage))


@dataclass(frozen=True)
class SteadyTorque:
    """Steady air-gap torque at a constant speed: ``mean + ripple cos(2 theta_e + phase)``.

    Attributes
    ----------
    mean : float
        Mean torque [N m] (positive sequence motoring plus negative sequence braking).
    ripple : float
        Amplitude of the torque ripple at twice the supply frequency [N m] (0 when balanced).
    phase : float
        Phase of the ripple against twice the supply angle [rad].
    current : float
        Peak stator current of the positive sequence [A].
    """

    mean: float
    ripple: float
    phase: float
    current: float


def steady_torque(motor: InductionMotor, rotor_speed: float, frequency: float | None = None,
                  voltage: float | None = None) -> SteadyTorque:
    """Steady torque of the dq model at constant ``rotor_speed`` [rad/s], supply unbalance included
    (``rotor_speed``, ``frequency`` and ``voltage`` may be arrays of equal shape: then elementwise).

    The stator flux and current are sums of a positive (``e^{j w t}``) and a negative sequence
    (``u e^{-j w t}``) part; ``T = 3/2 p Im(conj(psi_s) i_s)`` has the mean
    ``3/2 p (Im(conj(psi_1) i_1) + Im(conj(psi_2) i_2))`` and the ripple
    ``3/2 p Im((conj(psi_2) i_1 - psi_1 conj(i_2)) e^{2 j w t})``.
    """
    f = motor.supply_frequency if frequency is None else frequency
    v = motor.phase_voltage_peak * (1.0 if voltage is None else voltage / motor.supply_voltage)
    w = 2 * math.pi * np.asarray(f, dtype=float)
    if np.ndim(w) or np.ndim(rotor_speed) or np.ndim(v):            # a record's speeds: elementwise
        w, speed, v = np.broadcast_arrays(w, np.asarray(rotor_speed, float), np.asarray(v, float))
        out = np.empty((4, w.size))
        steady_torque_many(machine_constants(motor), w.ravel(), speed.ravel(), v.ravel(), out)
        return SteadyTorque(*out.reshape((4,) + w.shape))
    return SteadyTorque(*steady_torque_terms(machine_constants(motor), float(w), float(rotor_speed), float(v)))


# -- supply and the dq model --------------------------------------------------------------------
@dataclass(frozen=True)
class Supply:
    """Supply of the motor: direct-on-line, or a frequency ramp at constant V/f.

    Attributes
    ----------
    ramp_time : float
        Time to ramp the frequency from ``start_frequency`` to the rated one [s]; 0: direct-on-line.
    start_frequency : float
        Frequency at t = 0 of a ramp [Hz].
    voltage_floor : float
        Smallest voltage of a ramp as a fraction of rated (IR boost) [-].
    """

    ramp_time: float = 0.0
    start_frequency: float = 0.0
    voltage_floor: float = 0.05

    def state(self, motor: InductionMotor, t: float) -> tuple[float, float, float]:
        """``(theta_e [rad], omega_e [rad/s], v_peak [V])`` of the positive sequence at time ``t`` [s]
        (:func:`ddgsa.mbs.machines.supply_state`; elementwise for an array ``t``)."""
        if np.ndim(t):
            t = np.asarray(t, dtype=float)
            out = np.empty((3, t.size))
            supply_many(machine_constants(motor, self), t.ravel(), out)      # its cut flag is 0: the supply's own state
            return out[0].reshape(t.shape), out[1].reshape(t.shape), out[2].reshape(t.shape)
        return supply_state(machine_constants(motor, self), float(t))


@functools.lru_cache(maxsize=64)
def machine_constants(motor: InductionMotor, supply: Supply | None = None, cut: bool = False) -> NDArray[np.float64]:
    """The constants array of the compiled machine functions (:mod:`ddgsa.mbs.machines`, its layout)
    for ``motor`` on ``supply`` (default direct-on-line), cut at ``t = 0`` when ``cut``; kept for the
    latest motors and supplies (a dq run asks at every step), so it must not be modified."""
    s = Supply() if supply is None else supply
    return np.array([motor.stator_resistance, motor.rotor_resistance, motor.stator_inductance, motor.rotor_inductance,
                     motor.magnetising_inductance, motor.pole_pairs, motor.supply_unbalance,
                     2 * math.pi * motor.supply_frequency, motor.phase_voltage_peak, s.ramp_time,
                     2 * math.pi * s.start_frequency, s.voltage_floor, 1.0 if cut else 0.0], dtype=float)


def currents(motor: InductionMotor, flux: NDArray[np.float64]) -> tuple[complex, complex]:
    """Stator and rotor current space vectors [A] from ``flux = (psi_sd, psi_sq, psi_rd, psi_rq)`` [Wb]."""
    return dq_currents(machine_constants(motor), np.asarray(flux, dtype=float))


def dq_derivatives(motor: InductionMotor, supply: Supply, t: float, flux: NDArray[np.float64],
                   rotor_speed: float) -> tuple[NDArray[np.float64], float]:
    """Rates of the four flux linkages [Wb/s] and the air-gap torque [N m] of the dq model (the kernel's
    compiled :func:`ddgsa.mbs.machines.dq_rates`).

    Parameters
    ----------
    t : float
        Time [s] (for the supply state).
    flux : ndarray, shape (4,)
        ``(psi_sd, psi_sq, psi_rd, psi_rq)`` [Wb] in the frame of the positive-sequence supply angle.
    rotor_speed : float
        Mechanical rotor speed ``w_m`` [rad/s].
    """
    rates, torque = dq_rates(machine_constants(motor, supply), float(t), np.asarray(flux, dtype=float),
                             float(rotor_speed))
    return rates, float(torque)


def phase_current(motor: InductionMotor, supply: Supply, t: float, flux: NDArray[np.float64]) -> float:
    """Instantaneous phase-a stator current [A]: ``Re(i_s e^{j theta_e})``."""
    theta = supply.state(motor, t)[0]
    i_s, _ = currents(motor, flux)
    return float((i_s * complex(math.cos(theta), math.sin(theta))).real)

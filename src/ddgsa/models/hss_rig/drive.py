"""The motor as kernel parts, at the two fidelities, and the supply a scene gives it.

``kloss``
    The kernel's compiled :meth:`ddgsa.mbs.TorqueLaw.machine`: the steady torque of the
    equivalent circuit at the instantaneous supply frequency, voltage and rotor speed
    (:func:`ddgsa.mbs.machines.induction_torque`, as :func:`~ddgsa.models.hss_rig.motor.steady_torque`:
    mean plus the twice-line-frequency ripple of a supply unbalance). No flux dynamics.
``dq``
    :class:`DqMachine`: the fifth-order machine, its four fluxes carried by a
    :class:`ddgsa.mbs.first_order.FirstOrderStates` body and the rotor speed by the motor body.

The converter holds V/f constant: a scene at synchronous speed ``n`` [rpm] supplies
``f = p n / 60`` at ``V_rated f / 50``; a coast-down cuts the supply at ``t = 0``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ddgsa.errors import ModelError
from ddgsa.mbs import Marker, TorqueLaw
from ddgsa.mbs.bodies import Body, MarkerState
from ddgsa.mbs.elements import DQ_MACHINE, CompiledForm, Element, stacked
from ddgsa.mbs.first_order import FirstOrderStates
from ddgsa.mbs.machines import dq_rates, dq_wrench, induction_torque, supply_many, supply_on, torque_many
from ddgsa.models.hss_rig.motor import (InductionMotor, Supply, machine_constants, phase_current,
                                        sequence_phasors, steady_torque)
from ddgsa.models.hss_rig.scenes import RigScene

Array = NDArray[np.float64]
RATED_FREQUENCY = 50.0
"""Rated supply frequency of the motor data [Hz]."""
FLUX_STATES = ("psi_sd", "psi_sq", "psi_rd", "psi_rq")


@dataclass(frozen=True)
class Drive:
    """The motor and its supply for one scene.

    Attributes
    ----------
    motor : InductionMotor
        Equivalent circuit with the scene's supply frequency and voltage (constant V/f).
    supply : Supply
        Direct-on-line or ramp.
    cut : bool
        Supply off for ``t > 0`` (coast-down).
    """

    motor: InductionMotor
    supply: Supply
    cut: bool = False

    def state(self, t: float) -> tuple[float, float, float]:
        """``(theta_e, omega_e, v_peak)`` of the supply at ``t`` [s] (voltage 0 once cut)."""
        return supply_on(self.constants, float(t))

    def states(self, t: Array) -> tuple[Array, Array, Array]:
        """:meth:`state` along the times ``t`` [s] (n_t,): ``(theta_e, omega_e, v_peak)`` (n_t,) each."""
        t = np.asarray(t, dtype=float)
        out = np.empty((3, t.size))
        supply_many(self.constants, t.ravel(), out)
        return out[0].reshape(t.shape), out[1].reshape(t.shape), out[2].reshape(t.shape)

    @cached_property
    def constants(self) -> Array:
        """The motor, its supply and the cut as the compiled machine functions read them
        (:func:`~ddgsa.models.hss_rig.motor.machine_constants`, :mod:`ddgsa.mbs.machines`)."""
        return machine_constants(self.motor, self.supply, self.cut)


def drive_for(p: Mapping[str, float], scene: RigScene, pole_pairs: int = 2) -> Drive:
    """The motor of parameter set ``p`` supplied as ``scene`` asks (see the module)."""
    f = pole_pairs * scene.speed_rpm / 60.0
    motor = InductionMotor(
        stator_resistance=p["stator_resistance"], rotor_resistance=p["rotor_resistance"],
        stator_leakage_inductance=p["stator_leakage_inductance"], rotor_leakage_inductance=p["rotor_leakage_inductance"],
        magnetising_inductance=p["magnetising_inductance"], pole_pairs=pole_pairs,
        supply_voltage=p["supply_voltage"] * f / RATED_FREQUENCY, supply_frequency=f,
        supply_unbalance=p["supply_unbalance"])
    supply = Supply(ramp_time=scene.ramp_time) if scene.kind == "startup" else Supply()
    return Drive(motor, supply, cut=scene.kind == "coastdown")


def kloss_torque_at(drive: Drive, t: float, speed: float) -> float:
    """Air-gap torque [N m] of the steady equivalent circuit at time ``t`` and rotor ``speed`` [rad/s]
    (the compiled :func:`ddgsa.mbs.machines.induction_torque`)."""
    return induction_torque(drive.constants, float(t), float(speed))


def kloss_along(drive: Drive, t: Array, speed: Array) -> tuple[Array, Array]:
    """Air-gap torque [N m] and phase-a current [A] of the steady equivalent circuit (both sequences)
    along a record: times ``t`` [s], rotor ``speed`` [rad/s] (n_t,); :func:`kloss_torque_at` elementwise.
    Zero where the supply is off."""
    t, speed = np.broadcast_arrays(np.asarray(t, dtype=float), np.asarray(speed, dtype=float))
    torque = np.empty(t.size)
    torque_many(drive.constants, t.ravel(), speed.ravel(), torque)
    theta, w, v = drive.states(t)
    on = (v != 0.0) & (w > 0.0)
    w_on = np.where(on, w, 1.0)
    i1 = sequence_phasors(drive.motor, w_on, speed, v)[0]
    i2 = sequence_phasors(drive.motor, -w_on, speed, drive.motor.supply_unbalance * v)[0]
    current = np.where(on, (i1 * np.exp(1j * theta) + i2 * np.exp(-1j * theta)).real, 0.0)
    return torque.reshape(t.shape), current


def kloss_parts(drive: Drive):
    """``motor_parts`` for :func:`ddgsa.models.hss_rig.rig.build`: the kernel's compiled machine torque
    law on the motor rotor (:meth:`ddgsa.mbs.elements.TorqueLaw.machine`)."""
    def parts(marker: Marker) -> tuple[list[Body], list[Element]]:
        return [], [TorqueLaw.machine(marker, drive.constants, name="motor")]
    return parts


def steady_flux(drive: Drive, speed: float) -> Array:
    """Fluxes ``(psi_sd, psi_sq, psi_rd, psi_rq)`` [Wb] of the balanced steady state at ``speed`` [rad/s], t = 0."""
    _, w, v = drive.state(0.0)
    _, _, psi_s, psi_r = sequence_phasors(drive.motor, w, speed, v)
    return np.array([psi_s.real, psi_s.imag, psi_r.real, psi_r.imag])


class DqMachine(Element):
    """The dq machine between the motor rotor (marker 0) and its flux states (marker 1).

    The torque acts about the rotor marker's x axis (reaction on the ground); the flux rates
    are applied to the :class:`FirstOrderStates` body. Physics and tangents (central differences
    over the four fluxes and the rotor speed) are the kernel's compiled
    :func:`~ddgsa.mbs.machines.dq_wrench`.
    """

    def __init__(self, rotor: Marker, flux: Marker, drive: Drive, name: str = "motor") -> None:
        self.markers = (rotor, flux)
        self.drive, self.name = drive, name

    def rates(self, t: float, psi: Array, speed: float) -> tuple[Array, float]:
        """Flux rates [Wb/s] and air-gap torque [N m] at ``t`` for fluxes ``psi`` and rotor ``speed`` (0 V once cut)."""
        rates, torque = dq_rates(self.drive.constants, float(t), np.asarray(psi, dtype=float), float(speed))
        return rates, float(torque)

    def compiled(self) -> CompiledForm:
        """The machine's constants (:func:`~ddgsa.models.hss_rig.motor.machine_constants`): the packed system
        runs :func:`~ddgsa.mbs.machines.dq_wrench` with them."""
        return CompiledForm(DQ_MACHINE, self.drive.constants.copy())

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, Array]:
        _, a, v, w = stacked(states)
        out, damping = dq_wrench(self.drive.constants, float(t), a, w, v, 0, 1)
        return out, None, damping

    def phase_current(self, t: float, psi: Array) -> float:
        """Phase-a stator current [A] at time ``t`` from the fluxes ``psi`` [Wb]."""
        return phase_current(self.drive.motor, self.drive.supply, t, psi)


def dq_parts(drive: Drive, initial_flux: Array | None = None):
    """``motor_parts`` for :func:`ddgsa.models.hss_rig.rig.build`: the flux-state body and the dq machine."""
    def parts(marker: Marker) -> tuple[list[Body], list[Element]]:
        flux = FirstOrderStates("flux", FLUX_STATES, initial_flux)
        return [flux], [DqMachine(marker, flux.marker(), drive)]
    return parts


def steady_speed(drive: Drive, load_torque: float, load_exponent: float, rated_speed: float) -> float:
    """Rotor speed [rad/s] where the mean circuit torque meets the load law (the steady operating point)."""
    ws = 2 * math.pi * drive.motor.supply_frequency / drive.motor.pole_pairs

    def balance(w: float) -> float:
        return steady_torque(drive.motor, w).mean - load_torque * (w / rated_speed) ** load_exponent

    if balance(1e-9 * ws) <= 0:
        raise ModelError(f"the motor cannot start against the load: {load_torque} N m at standstill")
    top = ws * (1 - 1e-12)
    if balance(top) >= 0.0:                     # no load: the rotor runs at the synchronous speed
        return top
    return float(brentq(balance, 1e-9 * ws, top, xtol=1e-12))

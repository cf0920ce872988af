"""Reference turbines: quasi-steady rotor aerodynamics and their variable-speed, pitch-regulated control.

Two rotors, :data:`ROTORS` by name: ``nrel5mw`` (:data:`NREL5MW`, the default of every model but
``generator_radial``) and ``iea15mw`` (:data:`IEA15MW`, below). The default reference is the **NREL 5-MW** rotor (Jonkman et al. 2009, NREL/TP-500-38060: radius 63 m,
rated 5 MW at 11.4 m/s, 12.1 rpm, Cp,max 0.466 at tip-speed ratio 7.5 and zero pitch), run as a
direct drive (no gearbox) -- the class of the seed paper's turbine (rotor 40 t, pitch from about
11 m/s). Aerodynamic coefficients come from the ROSCO Cp/Ct/Cq table shipped in
``ddgsa/data`` (Apache-2.0, see its NOTICE). Hub height 80 m and shaft tilt 4 deg follow seed 000
Table 2. Controller (after the NREL 5-MW baseline, converted to rotor speed):

- region 2: generator torque ``k w^2``, ``k = 0.5 rho pi R^5 Cp,max / lambda_opt^3``;
- region 1.5: a steep linear torque ramp holding the minimum rotor speed (6.9 rpm);
- region 2.5: a linear torque ramp from ``k (0.95 w_rated)^2`` to rated torque at rated speed;
- region 3: torque ``Q_rated = P_rated / w_rated`` (constant torque above rated) and a
  gain-scheduled PI pitch controller on the rotor-speed error, ``K_P = 1.826 s``, ``K_I = 0.783`` (NREL 5-MW 0.01883 s and 0.008069 times the
  gearbox ratio 97), scheduled by ``1 / (1 + beta / 6.30 deg)``, pitch rate within 8 deg/s.

The **IEA 15 MW** rotor (:data:`IEA15MW`; Gaertner et al. 2020, NREL/TP-5000-75698, data of the
public IEA-15-240-RWT repository, Apache-2.0, shipped in ``ddgsa/data``, see its NOTICE): radius
120.97 m, hub radius 3.97 m, hub height 150 m, shaft tilt 6 deg, drive-train inertia 3.1246e8 kg m^2
(ROSCO ``WE_Jtot``), Cp/Ct/Cq table ``Cp_Ct_Cq.IEA15MW.txt`` (ROSCO, written for the same rotor). Its
controller in this module's structure, from the turbine's ROSCO ``DISCON.IN``: rated rotor speed
0.79168 rad/s (7.56 rpm, ``PC_RefSpd``), rated torque 19.787 MN m (``VS_RtTq``: 15 MW electrical
at the generator efficiency 95.756 %, so a shaft power of 15.665 MW), minimum speed 5 rpm
(``VS_MinOMSpd``), pitch rate 2 deg/s (``PC_MaxRat``); PI gains ``K_P = 2.373 s``, ``K_I = 0.2477``
scheduled by ``1 / (1 + beta / 3.50 deg)``: the knee is the least-squares fit (in log) of ROSCO's
``PC_GS_KI`` schedule, the gains are ROSCO's at its first scheduled pitch, 3.69 deg (its ``PC_GS_KP``
falls faster at high pitch than this form can follow). Region 2 tracks ``k w^2`` with the table's
optimum at fine pitch (ROSCO tracks the tip-speed ratio 9 with a wind-speed estimator; peak shaving
and the minimum-pitch schedule are not modelled).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from importlib.resources import files

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq


@dataclass(frozen=True)
class PerformanceTable:
    """Rotor power, thrust and torque coefficients over tip-speed ratio x pitch.

    Attributes
    ----------
    tsr : ndarray (n_tsr,)
        Tip-speed ratios [-], ascending.
    pitch : ndarray (n_pitch,)
        Blade pitch angles [rad], ascending.
    cp, ct : ndarray (n_tsr, n_pitch)
        Power and thrust coefficients [-]; ``cq = cp / tsr``.
    """

    tsr: NDArray[np.float64]
    pitch: NDArray[np.float64]
    cp: NDArray[np.float64]
    ct: NDArray[np.float64]

    @classmethod
    def from_rosco(cls, text: str) -> "PerformanceTable":
        """Parse a ROSCO ``Cp_Ct_Cq`` text file."""
        lines = text.splitlines()

        def after(header: str) -> int:
            return next(i for i, line in enumerate(lines) if header in line) + 1

        pitch_deg = np.array(lines[after("Pitch angle vector")].split(), dtype=float)
        tsr = np.array(lines[after("TSR vector")].split(), dtype=float)

        def block(header: str) -> NDArray[np.float64]:
            i = after(header)
            rows = [line.split() for line in lines[i:i + tsr.size + 2] if line.strip()]
            return np.array(rows[:tsr.size], dtype=float)

        return cls(tsr, np.deg2rad(pitch_deg), block("Power coefficient"), block("Thrust coefficient"))

    @cached_property
    def cq(self) -> NDArray[np.float64]:
        """Torque coefficient ``cp / tsr`` [-]."""
        return self.cp / self.tsr[:, None]

    def lookup(self, table: NDArray[np.float64], tsr: NDArray[np.float64] | float,
               pitch: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Bilinear interpolation of ``table`` (clamped to the table's range)."""
        return bilinear(self.tsr, self.pitch, table, np.asarray(tsr, float), np.asarray(pitch, float))


def bilinear(x: NDArray[np.float64], y: NDArray[np.float64], table: NDArray[np.float64],
             xq: NDArray[np.float64], yq: NDArray[np.float64]) -> NDArray[np.float64]:
    """Bilinear interpolation on a rectilinear grid, clamped at its edges (vectorised)."""
    xq = np.clip(xq, x[0], x[-1])
    yq = np.clip(yq, y[0], y[-1])
    i = np.clip(np.searchsorted(x, xq) - 1, 0, x.size - 2)
    j = np.clip(np.searchsorted(y, yq) - 1, 0, y.size - 2)
    tx = (xq - x[i]) / (x[i + 1] - x[i])
    ty = (yq - y[j]) / (y[j + 1] - y[j])
    return ((1 - tx) * (1 - ty) * table[i, j] + tx * (1 - ty) * table[i + 1, j]
            + (1 - tx) * ty * table[i, j + 1] + tx * ty * table[i + 1, j + 1])


def _table(name: str) -> PerformanceTable:
    return PerformanceTable.from_rosco((files("ddgsa") / "data" / name).read_text())


def _nrel5mw_table() -> PerformanceTable:
    return _table("Cp_Ct_Cq.NREL5MW.txt")


@dataclass(frozen=True)
class Turbine:
    """Rotor geometry, inertia, aerodynamics and controller of the reference turbine (SI units).

    Attributes
    ----------
    rotor : str
        Name of the rotor in :data:`ROTORS`; the BEM rotor reads its blade by it
        (:data:`ddgsa.loads.bem.BLADES`).
    rotor_radius : float [m]
    hub_radius : float [m]
    hub_height : float [m]
    tilt_deg : float
        Shaft tilt, hub end up [deg].
    air_density : float [kg/m^3]
    rotor_inertia : float
        Polar inertia of rotor and generator rotor about the shaft [kg m^2].
    rated_power : float
        Rated aerodynamic (shaft) power [W].
    rated_speed, min_speed : float
        Rated and minimum rotor speed [rad/s].
    kp, ki : float
        Pitch PI gains at zero pitch [s], [-] (rad pitch per rad/s speed error).
    gain_knee : float
        Pitch at which the PI gains halve [rad].
    pitch_rate : float
        Pitch rate limit [rad/s].
    region25_fraction : float
        Rotor speed, as a fraction of rated, where the torque ramps linearly to rated torque [-].
    n_stations : int
        Radial stations per blade (equal-area annuli).
    table : PerformanceTable
    """

    rotor: str = "nrel5mw"
    rotor_radius: float = 63.0
    hub_radius: float = 1.5
    hub_height: float = 80.0
    tilt_deg: float = 4.0
    air_density: float = 1.225
    rotor_inertia: float = 3.8677e7 + 7.5e3
    rated_power: float = 5.0e6
    rated_speed: float = 12.1 * np.pi / 30.0
    min_speed: float = 6.9 * np.pi / 30.0
    kp: float = 0.01882681 * 97.0
    ki: float = 0.008068634 * 97.0
    gain_knee: float = np.deg2rad(6.302336)
    pitch_rate: float = np.deg2rad(8.0)
    region25_fraction: float = 0.95
    n_stations: int = 5
    table: PerformanceTable = field(default_factory=_nrel5mw_table, compare=False, repr=False)

    @property
    def area(self) -> float:
        """Swept area [m^2]."""
        return np.pi * self.rotor_radius ** 2

    @cached_property
    def optimum(self) -> tuple[float, float, float]:
        """Maximum power coefficient at fine pitch (0, where the controller holds the blades below
        rated), its tip-speed ratio and that pitch [-, -, rad] (over the table's tip-speed ratios)."""
        cp = self.table.lookup(self.table.cp, self.table.tsr, np.zeros_like(self.table.tsr))
        i = int(np.argmax(cp))
        return float(cp[i]), float(self.table.tsr[i]), 0.0

    @property
    def k_opt(self) -> float:
        """Region-2 torque gain ``k`` in ``Q = k w^2`` [N m s^2/rad^2]."""
        cp, tsr, _ = self.optimum
        return 0.5 * self.air_density * self.area * self.rotor_radius ** 3 * cp / tsr ** 3

    @property
    def rated_torque(self) -> float:
        """Rated generator torque [N m]."""
        return self.rated_power / self.rated_speed

    @cached_property
    def stations(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Radial stations [m] (centroids of equal-area annuli) and the area each blade element covers [m^2]."""
        edges = np.sqrt(np.linspace(self.hub_radius ** 2, self.rotor_radius ** 2, self.n_stations + 1))
        r = (2.0 / 3.0) * (edges[1:] ** 3 - edges[:-1] ** 3) / (edges[1:] ** 2 - edges[:-1] ** 2)
        area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2) / 3.0
        return r, area

    def generator_torque(self, speed: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Controller torque demand at rotor speed ``speed`` [rad/s] -> [N m] (regions 1.5, 2, 2.5, 3)."""
        w = np.asarray(speed, dtype=float)
        w0, w25 = 0.9 * self.min_speed, self.region25_fraction * self.rated_speed
        q_min, q25 = self.k_opt * self.min_speed ** 2, self.k_opt * w25 ** 2
        q = np.where(w < self.min_speed, np.maximum(q_min * (w - w0) / (self.min_speed - w0), 0.0),
                     self.k_opt * w ** 2)
        q = np.where(w >= w25, q25 + (self.rated_torque - q25) * (w - w25) / (self.rated_speed - w25), q)
        return np.minimum(q, self.rated_torque)

    def steady_state(self, wind_speed: float) -> dict[str, float]:
        """Steady operating point in uniform wind ``wind_speed`` [m/s].

        Returns rotor speed [rad/s], pitch [rad], tip-speed ratio, power [W], thrust [N],
        aerodynamic torque [N m] and the power, thrust coefficients.
        """
        rho, a, big_r = self.air_density, self.area, self.rotor_radius
        fine = 0.0

        def aero_torque(w: float, beta: float) -> float:
            lam = w * big_r / wind_speed
            return float(0.5 * rho * a * big_r * self.table.lookup(self.table.cq, lam, beta) * wind_speed ** 2)

        # below rated: rotor speed where aerodynamic and generator torque balance at fine pitch
        lo, hi = 0.2 * self.min_speed, self.rated_speed
        f_lo = aero_torque(lo, fine) - float(self.generator_torque(lo))
        f_hi = aero_torque(hi, fine) - float(self.generator_torque(hi))
        if f_lo > 0 and f_hi < 0:
            w = brentq(lambda s: aero_torque(s, fine) - float(self.generator_torque(s)), lo, hi, xtol=1e-12)
            beta = fine
        else:
            # above rated: rated speed, pitch where the aerodynamic torque equals rated torque
            w = self.rated_speed
            beta = brentq(lambda b: aero_torque(w, b) - self.rated_torque, fine, self.table.pitch[-1],
                          xtol=1e-12)
        lam = w * big_r / wind_speed
        q = aero_torque(w, beta)
        ct = float(self.table.lookup(self.table.ct, lam, beta))
        return {"rotor_speed": w, "pitch": beta, "tsr": lam, "cp": q * w / (0.5 * rho * a * wind_speed ** 3),
                "ct": ct, "power": q * w, "thrust": 0.5 * rho * a * ct * wind_speed ** 2, "aero_torque": q}

    @cached_property
    def rated_wind_speed(self) -> float:
        """Wind speed where rated torque is reached at rated speed and fine pitch [m/s]."""
        big_r, w = self.rotor_radius, self.rated_speed

        def excess(v: float) -> float:
            cq = float(self.table.lookup(self.table.cq, w * big_r / v, 0.0))
            return 0.5 * self.air_density * self.area * big_r * cq * v ** 2 - self.rated_torque

        return float(brentq(excess, 5.0, 25.0, xtol=1e-10))


NREL5MW = Turbine()


IEA_GENERATOR_EFFICIENCY = 0.95756
"""Generator efficiency of the IEA 15 MW turbine (ROSCO ``VS_GenEff``) [-]."""
IEA15MW = Turbine(
    rotor="iea15mw", rotor_radius=120.97, hub_radius=3.97, hub_height=150.0, tilt_deg=6.0,
    rotor_inertia=312456272.0, rated_power=19786767.46773 * 0.79168, rated_speed=0.79168,
    min_speed=5.0 * np.pi / 30.0, kp=2.373, ki=0.2477, gain_knee=np.deg2rad(3.504), pitch_rate=0.0349,
    table=_table("Cp_Ct_Cq.IEA15MW.txt"))
"""The IEA 15 MW reference rotor and its controller (module docstring); ``rated_power`` is the shaft
power, 15 MW electrical over :data:`IEA_GENERATOR_EFFICIENCY`."""
ROTORS = {"nrel5mw": NREL5MW, "iea15mw": IEA15MW}
"""The reference rotors by name (the ``rotor`` option of the models that offer one)."""

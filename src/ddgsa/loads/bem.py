"""Blade-element momentum (BEM) rotor: the ``bem`` loads fidelity.

Each of the three rotating blades carries the 17 elements of the NREL 5-MW blade (Jonkman et
al. 2009, NREL/TP-500-38060, Table 2-1: chord, twist and the DU/NACA 64 airfoil polars, shipped in
``ddgsa/data``, see its NOTICE), or for the IEA 15 MW rotor (``Turbine.rotor == "iea15mw"``) 16
elements of its AeroDyn blade with their own FFA-W3 polars (:data:`IEA15MW_BLADE`). At every time step each element is solved by blade-element
momentum theory in the wind sampled from the turbulence box of :func:`ddgsa.loads.wind_field`
(the grid of :func:`ddgsa.loads.hubloads.grid_points`, bilinear in azimuth as the quasi-steady
rotor samples it and linear in radius between the hub centre and the grid's rings):

- the relative flow: axial ``U_n (1 - a (1 + S))``, tangential ``U_t (1 + a')`` with
  ``U_t = Omega r + U_y cos psi + U_z sin psi`` (the in-plane wind against the blade's motion);
- Prandtl tip and hub losses ``F = (2/pi)^2 acos(exp(-B (R - r) / (2 r sin phi)))
  acos(exp(-B (r - R_h) / (2 R_h sin phi)))``;
- momentum: ``k = sigma C_l cos phi / (4 F sin^2 phi)``, ``a = k / (1 + k)`` up to ``a = 0.4``
  and Buhl's empirical high-thrust branch above; ``k' = sigma C_l / (4 F cos phi)``,
  ``a' = k' / (1 - k')`` (lift-only induction, as AeroDyn's NREL 5-MW deck: ``AIDrag``,
  ``TIDrag`` false; with the drag terms where the blade says so, :attr:`Blade.drag_in_induction`,
  as the IEA 15 MW deck), solved for the inflow angle by Brent's method on Ning's (2014) bracketed
  residual, as CCBlade and AeroDyn's BEMT do (unique, no iteration history, no spurious
  ``a = 1`` fixed point);
- skewed wake (Glauert / Pitt-Peters, AeroDyn's ``SkewRedistr_Mod = 1``): after the solve, the
  axial induction is redistributed by ``S = (15 pi / 32) (r / R) tan(chi / 2) cos(psi - psi_w)``,
  with ``psi_w`` the azimuth of the disc-averaged in-plane wind and ``chi`` the wake skew angle of
  the disc-averaged
  wind plus the mean axial induced velocity of the elements in 0.5-0.8 R (previous step), and
  the loads come from the redistributed velocity triangle;
- tower shadow: potential flow around the tower (AeroDyn ``TwrPotent = 1``) for blade points below
  the hub, ``u / U = 1 - R_t^2 (x^2 - y^2) / (x^2 + y^2)^2``, ``v / U = 2 R_t^2 x y / (x^2 + y^2)^2``
  at ``x = overhang + |z| sin(tilt)`` upwind of the tower axis (NREL 5-MW tower diameter, 6 m at
  the ground to 3.87 m at 87.6 m, and overhang 5.0191 m).

Element loads ``0.5 rho W^2 c dr (C_l cos phi + C_d sin phi)`` (normal) and
``0.5 rho W^2 c dr (C_l sin phi - C_d cos phi)`` (tangential) are summed into the hub loads of
:mod:`ddgsa.loads.hubloads` (same frame, same controller, same outputs). No dynamic inflow, no
dynamic stall and rigid blades: the model resolves what a Cp/Ct table cannot, the azimuthal
variation of the induction and of the blade aerodynamics in inclined and yawed inflow.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from importlib.resources import files

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.loads.hubloads import N_AZIMUTH, controller_step, record_and_step, torque_law
from ddgsa.loads.rotor import IEA15MW, Turbine

#: Pitt-Peters skewed-wake redistribution constant (AeroDyn's default SkewRedistrFactor)
SKEW_FACTOR = 15.0 * np.pi / 32.0
#: angle-of-attack step of the polar tables the kernel reads [rad] (0.1 deg)
ALPHA_STEP = np.deg2rad(0.1)


def _read_table(name: str) -> list[list[str]]:
    text = (files("ddgsa") / "data" / name).read_text()
    return [line.split() for line in text.splitlines() if line.strip() and not line.startswith("#")]


def _polars_on_grid(name: str, alpha: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """Each airfoil's (cl, cd) of the polar file ``name`` in ``ddgsa/data`` linearly interpolated onto
    ``alpha`` [rad], shape (2, n_alpha)."""
    rows = _read_table(name)
    out = {}
    for airfoil in dict.fromkeys(r[0] for r in rows):
        tab = np.array([r[1:4] for r in rows if r[0] == airfoil], dtype=float)
        a = np.deg2rad(tab[:, 0])
        out[airfoil] = np.vstack([np.interp(alpha, a, tab[:, 1]), np.interp(alpha, a, tab[:, 2])])
    return out


@dataclass(frozen=True)
class Blade:
    """Aerodynamic blade of a reference rotor and the tower it passes (SI units); the defaults are the
    NREL 5-MW's, :data:`IEA15MW_BLADE` the IEA 15 MW's.

    Attributes
    ----------
    blade_file, polar_file : str
        Element table (radius, width, chord [m], twist [deg], airfoil) and airfoil polars (airfoil,
        angle of attack [deg], lift, drag coefficients) in ``ddgsa/data`` (see its NOTICE).
    n_blades : int
    tip_radius, hub_radius : float
        Rotor radius R and blade-root radius R_h [m].
    overhang : float
        Upwind distance of the rotor centre from the tower axis [m].
    tower_base_diameter, tower_top_diameter, tower_height : float
        Linear tower taper [m] (NREL 5-MW: 6, 3.87 m over 87.6 m).
    tower_shadow, skewed_wake, tip_loss, hub_loss : bool
        Switch the model's corrections (all on by default).
    drag_in_induction : bool
        Include the drag in the momentum inductions (AeroDyn's ``AIDrag``, ``TIDrag``: true in the
        IEA 15 MW deck, false in the NREL 5-MW deck, whose default is kept):
        ``k = sigma (C_l cos phi + C_d sin phi) / (4 F sin^2 phi)``,
        ``k' = sigma (C_l sin phi - C_d cos phi) / (4 F sin phi cos phi)``.
    refine : int
        Sub-elements per Table 2-1 element (>= 1; 1, the 17 published elements, is the default,
        converged within the tolerances of docs/loads.md): each element split into ``refine``
        equal widths, chord and twist linear in radius between the published element centres
        (held beyond the first and last), the parent's airfoil.
    """

    blade_file: str = "NREL5MW_blade.txt"
    polar_file: str = "NREL5MW_polars.txt"
    n_blades: int = 3
    tip_radius: float = 63.0
    hub_radius: float = 1.5
    overhang: float = 5.0191
    tower_base_diameter: float = 6.0
    tower_top_diameter: float = 3.87
    tower_height: float = 87.6
    tower_shadow: bool = True
    skewed_wake: bool = True
    tip_loss: bool = True
    hub_loss: bool = True
    drag_in_induction: bool = False
    refine: int = 1

    def __post_init__(self) -> None:
        if isinstance(self.refine, bool) or not isinstance(self.refine, int) or self.refine < 1:
            raise ValueError(f"Blade.refine must be an integer >= 1, got {self.refine!r}")

    @cached_property
    def elements(self) -> dict[str, NDArray[np.float64]]:
        """Element radius ``r``, width ``dr``, ``chord`` [m], ``twist`` [rad] and polars ``cl``, ``cd``
        (n_elem, n_alpha) on ``alpha`` [rad] (uniform, step :data:`ALPHA_STEP`, -pi to pi)."""
        rows = _read_table(self.blade_file)
        geo = np.array([r[:4] for r in rows], dtype=float)
        k = self.refine
        frac = (np.arange(k) + 0.5) / k - 0.5                    # sub-element centres in parent widths
        r = (geo[:, :1] + geo[:, 1:2] * frac).ravel()
        alpha = np.arange(-np.pi, np.pi + 0.5 * ALPHA_STEP, ALPHA_STEP)
        polars = _polars_on_grid(self.polar_file, alpha)
        coeffs = np.repeat(np.stack([polars[row[4]] for row in rows]), k, axis=0)
        return {"r": r, "dr": np.repeat(geo[:, 1] / k, k), "chord": np.interp(r, geo[:, 0], geo[:, 2]),
                "twist": np.deg2rad(np.interp(r, geo[:, 0], geo[:, 3])), "alpha": alpha,
                "cl": np.ascontiguousarray(coeffs[:, 0]), "cd": np.ascontiguousarray(coeffs[:, 1])}

    def parameters(self) -> NDArray[np.float64]:
        """The scalars the kernel reads, in its order."""
        return np.array([self.n_blades, self.tip_radius, self.hub_radius, self.overhang,
                         self.tower_base_diameter, self.tower_top_diameter, self.tower_height,
                         float(self.tower_shadow), float(self.skewed_wake), float(self.tip_loss),
                         float(self.hub_loss), float(self.drag_in_induction)])


NREL5MW_BLADE = Blade()
IEA15MW_BLADE = Blade(blade_file="IEA15MW_blade.txt", polar_file="IEA15MW_polars.txt",
                      tip_radius=IEA15MW.rotor_radius, hub_radius=IEA15MW.hub_radius, overhang=12.0976, tower_base_diameter=10.0, tower_top_diameter=6.5,
                      tower_height=144.386, drag_in_induction=True)
"""The IEA 15 MW blade (16 elements of the AeroDyn deck, ``ddgsa/data/IEA15MW_blade.txt``) and its
tower: ElastoDyn's overhang 12.0976 m and tower top 144.386 m, the monopile tower's 10 m base and
6.5 m top diameters; drag in the inductions as in its AeroDyn deck. Its 4 deg precone and the
blades' prebend are not modelled (docs/loads.md)."""
BLADES = {"nrel5mw": NREL5MW_BLADE, "iea15mw": IEA15MW_BLADE}
"""The blade of each reference rotor, by :attr:`ddgsa.loads.rotor.Turbine.rotor`."""

_PHI_TOL = 1e-6


@njit(cache=True)
def _polar(cl_tab: NDArray[np.float64], cd_tab: NDArray[np.float64], alpha0: float, dalpha: float,
           al: float) -> tuple[float, float]:  # pragma: no cover (compiled)
    """Lift and drag coefficients at angle of attack ``al`` [rad] (linear on the uniform grid)."""
    al = (al + np.pi) % (2.0 * np.pi) - np.pi
    x = (al - alpha0) / dalpha
    i = min(max(int(x), 0), cl_tab.size - 2)
    t = x - i
    return (1.0 - t) * cl_tab[i] + t * cl_tab[i + 1], (1.0 - t) * cd_tab[i] + t * cd_tab[i + 1]


@njit(cache=True)
def _induction(phi: float, un: float, ut: float, r: float, sigma: float, theta: float,
               cl_tab: NDArray[np.float64], cd_tab: NDArray[np.float64], alpha0: float, dalpha: float,
               prm: NDArray[np.float64]) -> tuple[float, float, float]:  # pragma: no cover (compiled)
    """Momentum inductions ``a, a'`` at inflow angle ``phi`` and Ning's residual
    ``sin phi / (1 - a) - (U_n / U_t) cos phi / (1 + a')`` (propeller-brake form for ``phi < 0``)."""
    n_b, big_r, r_hub = prm[0], prm[1], prm[2]
    cl, cd = _polar(cl_tab, cd_tab, alpha0, dalpha, phi - theta)
    sp, cp = np.sin(phi), np.cos(phi)
    cn, ct = cl, cl              # lift only: k = sigma C_l cos / (4 F sin^2), k' = sigma C_l / (4 F cos)
    if prm[11] > 0.0:            # drag included (AIDrag, TIDrag): C_n / cos and C_t / sin in those forms
        cn, ct = cl + cd * sp / cp, cl - cd * cp / sp
    s = max(abs(sp), 1e-9)
    f = 1.0
    if prm[9] > 0.0:
        f *= 2.0 / np.pi * np.arccos(min(np.exp(-0.5 * n_b * (big_r - r) / (r * s)), 1.0))
    if prm[10] > 0.0:
        f *= 2.0 / np.pi * np.arccos(min(np.exp(-0.5 * n_b * (r - r_hub) / (r_hub * s)), 1.0))
    f = max(f, 1e-6)
    k = sigma * cn * cp / (4.0 * f * sp * sp)
    kp = sigma * ct / (4.0 * f * cp)
    lam = un / ut
    if phi < 0.0:      # propeller brake: momentum does not hold, Ning's residual form
        return 0.0, 0.0, sp * (1.0 - k) - lam * cp * (1.0 - kp)
    if k <= 2.0 / 3.0:
        a = k / (1.0 + k)
    else:              # Buhl's empirical high-thrust branch (AeroDyn's BEMT), in terms of k
        g1 = 2.0 * f * k - (10.0 / 9.0 - f)
        g2 = max(2.0 * f * k - (4.0 / 3.0 - f) * f, 0.0)
        g3 = 2.0 * f * k - (25.0 / 9.0 - 2.0 * f)
        a = 1.0 - 0.5 / np.sqrt(g2) if abs(g3) < 1e-6 else (g1 - np.sqrt(g2)) / g3
    ap = kp / (1.0 - kp)
    return a, ap, sp / (1.0 - a) - lam * cp / (1.0 + ap)


@njit(cache=True)
def _solve_phi(lo: float, hi: float, un: float, ut: float, r: float, sigma: float, theta: float,
               cl_tab: NDArray[np.float64], cd_tab: NDArray[np.float64], alpha0: float, dalpha: float,
               prm: NDArray[np.float64]) -> tuple[bool, float]:  # pragma: no cover (compiled)
    """Root of the residual in ``[lo, hi]`` by Brent's method; (False, 0) without a sign change."""
    fa = _induction(lo, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha, prm)[2]
    fb = _induction(hi, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha, prm)[2]
    if fa * fb > 0.0:
        return False, 0.0
    a, b = lo, hi
    c, fc = a, fa
    d = e = b - a
    for _ in range(100):
        if fb * fc > 0.0:
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * 1e-16 * abs(b) + 0.5 * _PHI_TOL
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return True, b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2.0 * m * s, 1.0 - s
            else:
                q, rr = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - rr) - (b - a) * (rr - 1.0))
                q = (q - 1.0) * (rr - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0.0 else -tol)
        fb = _induction(b, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha, prm)[2]
    return True, b


@njit(cache=True)
def _element(un: float, ut: float, skew: float, r: float, chord: float, twist: float, pitch: float,
             cl_tab: NDArray[np.float64], cd_tab: NDArray[np.float64], alpha0: float, dalpha: float,
             prm: NDArray[np.float64]) -> tuple[float, float, float, float, float]:  # pragma: no cover
    """One element: Ning's bracketed BEM solve for the inflow angle (momentum region ``(0, pi/2]``,
    then the propeller brake ``[-pi/4, 0)``), then the skewed-wake redistribution of the axial
    induction and the loads of the redistributed velocity triangle (AeroDyn's order). Returns
    ``a`` (before redistribution), ``a'``, ``W^2`` [m^2/s^2], ``C_n``, ``C_t``."""
    sigma = prm[0] * chord / (2.0 * np.pi * r)
    theta = twist + pitch
    a = ap = 0.0
    if ut > 1e-6 and un > 1e-6:
        ok, phi = _solve_phi(1e-6, 0.5 * np.pi, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha, prm)
        if not ok:
            ok, phi = _solve_phi(-0.25 * np.pi, -1e-6, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha,
                                 prm)
        if ok:
            a, ap, _ = _induction(phi, un, ut, r, sigma, theta, cl_tab, cd_tab, alpha0, dalpha, prm)
    vn = un * (1.0 - a * (1.0 + skew))
    vt = ut * (1.0 + ap)
    phi = np.arctan2(vn, vt)
    cl, cd = _polar(cl_tab, cd_tab, alpha0, dalpha, phi - theta)
    sp, cp = np.sin(phi), np.cos(phi)
    return a, ap, vn * vn + vt * vt, cl * cp + cd * sp, cl * sp - cd * cp


@njit(cache=True)
def _sample(inflow: NDArray[np.float64], ti: int, c: int, ring_r: NDArray[np.float64], r: float, i0: int,
            i1: int, t: float, n_az: int) -> float:  # pragma: no cover (compiled)
    """Component ``c`` of the grid wind at radius ``r``, between grid azimuths i0, i1 (fraction t):
    linear in radius between the hub centre (point 0) and the rings, constant beyond the outer ring."""
    n_ring = ring_r.size
    j = 0
    while j < n_ring and ring_r[j] < r:
        j += 1
    if j == n_ring:
        p = 1 + (n_ring - 1) * n_az
        return (1.0 - t) * inflow[c, ti, p + i0] + t * inflow[c, ti, p + i1]
    p = 1 + j * n_az
    outer = (1.0 - t) * inflow[c, ti, p + i0] + t * inflow[c, ti, p + i1]
    if j == 0:
        inner, r_in = inflow[c, ti, 0], 0.0
    else:
        q = 1 + (j - 1) * n_az
        inner, r_in = (1.0 - t) * inflow[c, ti, q + i0] + t * inflow[c, ti, q + i1], ring_r[j - 1]
    s = (r - r_in) / (ring_r[j] - r_in)
    return (1.0 - s) * inner + s * outer


@njit(cache=True)
def _simulate_bem(inflow: NDArray[np.float64], spinup: int, n_az: int, dt: float, ring_r: NDArray[np.float64],
                  rad: NDArray[np.float64], dr: NDArray[np.float64], chord: NDArray[np.float64],
                  twist: NDArray[np.float64], cl: NDArray[np.float64], cd: NDArray[np.float64],
                  alpha0: float, dalpha: float, prm: NDArray[np.float64], rho: float, inertia: float,
                  hub_height: float, tilt: float, law: NDArray[np.float64], omega0: float, beta0: float,
                  ctl: NDArray[np.float64], fixed: bool,
                  record: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Time loop of the BEM rotor (see :func:`simulate_bem`); ``record`` (n, n_elem, 2), when it has
    ``spinup + n_t`` rows, receives blade 1's axial induction ``a (1 + S)`` and its skew term ``S``."""
    n_t = inflow.shape[1]
    n_r = rad.size
    n_b = int(prm[0])
    big_r = prm[1]
    out = np.empty((spinup + n_t, 10))
    omega, psi, beta = omega0, 0.0, beta0
    integ = ctl[6]
    vind_mean = 0.0
    n_pts = inflow.shape[2]
    for n in range(spinup + n_t):
        ti = (n_t - spinup + n) % n_t
        # disc-averaged wind (rings are equal-area), its in-plane direction and the wake skew angle
        mx_, my_, mz_ = 0.0, 0.0, 0.0
        for p in range(1, n_pts):
            mx_ += inflow[0, ti, p]
            my_ += inflow[1, ti, p]
            mz_ += inflow[2, ti, p]
        mx_ /= n_pts - 1
        my_ /= n_pts - 1
        mz_ /= n_pts - 1
        v_ip = np.sqrt(my_ * my_ + mz_ * mz_)
        ey, ez = (my_ / v_ip, mz_ / v_ip) if v_ip > 1e-9 else (0.0, 0.0)
        chi = np.arctan2(v_ip, max(mx_ - vind_mean, 1e-3))
        k_skew = SKEW_FACTOR * np.tan(0.5 * chi) if prm[8] > 0.0 else 0.0
        fx = fy = fz = mx = my = mz = 0.0
        vsum, nsum = 0.0, 0
        for b in range(n_b):
            az = psi + 2.0 * np.pi * b / n_b
            pos = (az / (2.0 * np.pi)) % 1.0 * n_az
            i0 = int(pos) % n_az
            i1 = (i0 + 1) % n_az
            t = pos - int(pos)
            c, s = np.cos(az), np.sin(az)
            proj = -s * ey + c * ez          # cos(psi - psi_w): blade direction on the in-plane wind
            for j in range(n_r):
                r = rad[j]
                ux = _sample(inflow, ti, 0, ring_r, r, i0, i1, t, n_az)
                uy = _sample(inflow, ti, 1, ring_r, r, i0, i1, t, n_az)
                uz = _sample(inflow, ti, 2, ring_r, r, i0, i1, t, n_az)
                if prm[7] > 0.0 and c < 0.0:          # tower shadow, blade below the hub
                    zb = -r * c
                    diam = prm[4] + (prm[5] - prm[4]) * min(max((hub_height - zb) / prm[6], 0.0), 1.0)
                    xt = prm[3] + zb * np.sin(tilt)
                    yt = -r * s
                    d2 = xt * xt + yt * yt
                    rt2 = 0.25 * diam * diam
                    uy += ux * 2.0 * rt2 * xt * yt / (d2 * d2)
                    ux *= 1.0 - rt2 * (xt * xt - yt * yt) / (d2 * d2)
                un = max(ux, 0.1)
                ut = omega * r + uy * c + uz * s
                skew = k_skew * (r / big_r) * proj
                a, ap, w2, cn, ct = _element(un, ut, skew, r, chord[j], twist[j], beta, cl[j], cd[j], alpha0,
                                             dalpha, prm)
                if record.shape[0] == out.shape[0] and b == 0:
                    record[n, j, 0] = a * (1.0 + skew)
                    record[n, j, 1] = skew
                if 0.5 * big_r <= r <= 0.8 * big_r:
                    vsum += a * un
                    nsum += 1
                q = 0.5 * rho * w2 * chord[j] * dr[j]
                fn, ft = q * cn, q * ct
                fx += fn
                fy -= ft * c
                fz -= ft * s
                mx += ft * r
                my += r * fn * c
                mz += r * fn * s
        vind_mean = vsum / max(nsum, 1)
        if fixed:
            q_gen = mx
        else:
            q_gen, beta, integ = controller_step(omega, beta, integ, dt, law, ctl)
        omega, psi = record_and_step(out, n, fx, fy, fz, mx, my, mz, omega, beta, q_gen, psi, dt, inertia)
    return out


def simulate_bem(turbine: Turbine, inflow: NDArray[np.float64], dt: float, initial: dict[str, float],
                 spinup: int = 0, blade: Blade | None = None, fixed: bool = False,
                 record: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Run the BEM rotor and its controller over the inflow on the grid.

    Parameters
    ----------
    turbine : Turbine
        Hub height, tilt, air density, inertia and controller (the rotor table is not used).
    inflow : ndarray (3, n_t, n_pts)
        Shaft-frame wind at :func:`ddgsa.loads.hubloads.grid_points` (hub centre first) [m/s].
    dt : float
        Time step [s].
    initial : dict
        ``rotor_speed`` [rad/s] and ``pitch`` [rad] to start from.
    spinup : int
        Steps run first over the last ``spinup`` samples of the (periodic) inflow and discarded.
    blade : Blade, optional
        The turbine's own (:data:`BLADES`) when not given.
    fixed : bool
        Hold rotor speed and pitch at ``initial`` (no controller; for verification).
    record : ndarray (spinup + n_t, n_elem, 2), optional
        Filled with blade 1's axial induction ``a (1 + S)`` and skew term ``S`` per element.

    Returns
    -------
    ndarray (n_t, 10)
        Fx, Fy, Fz [N], Mx, My, Mz [N m], rotor speed [rad/s], pitch [rad], generator torque
        [N m], azimuth of blade 1 [rad] (the columns of :func:`ddgsa.loads.hubloads.simulate_rotor`).
    """
    blade = BLADES[turbine.rotor] if blade is None else blade
    el = blade.elements
    ring_r, _ = turbine.stations
    spinup = min(int(spinup), inflow.shape[1])
    law, ctl = torque_law(turbine, initial["pitch"])
    rec = np.zeros((0, 1, 2)) if record is None else record
    out = _simulate_bem(np.ascontiguousarray(inflow), spinup, N_AZIMUTH, dt, ring_r, el["r"], el["dr"],
                        el["chord"], el["twist"], el["cl"], el["cd"], float(el["alpha"][0]), ALPHA_STEP,
                        blade.parameters(), turbine.air_density, turbine.rotor_inertia, turbine.hub_height,
                        np.deg2rad(turbine.tilt_deg), law, initial["rotor_speed"], initial["pitch"], ctl,
                        fixed, rec)
    return out[spinup:]

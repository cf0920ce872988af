"""Hub loads from three rotating blades in a turbulent, sheared, inclined wind field.

Frame (the drive-train frame, fixed to the non-rotating, tilted shaft axis):
**X** along the shaft from the hub towards the generator (downwind), **Z** perpendicular to it
in the vertical plane, upwards, **Y = Z x X** (to the left looking downwind). The shaft is
tilted by ``tilt_deg`` with the hub end up, so the horizontal wind has an in-plane component
along +Z. The rotor turns positively about +X; blade azimuth 0 points along +Z.

Quasi-steady rotor: each blade carries ``n_stations`` elements (centroids of equal-area
annuli, a third of the annulus each). An element at radius r sees the axial wind ``U`` and
the apparent tangential speed ``W = Omega r + U_y cos psi + U_z sin psi`` (in-plane wind
against the direction of motion), so its local tip-speed ratio is ``W R / (r U)``; its
thrust is ``0.5 rho C_t(lambda_loc, beta) U^2 dA`` and its torque
``0.5 rho C_q(lambda_loc, beta) R U^2 dA``, from the rotor's table. In uniform wind the
elements reproduce the rotor's C_t, C_q exactly; shear, inclination, tilt and turbulence make
them vary with azimuth, which gives the tilt/yaw moments (mean, 1P per blade, 3P on the hub).

Outputs are the **aerodynamic** loads only: rotor and generator weight and the tilt component
of gravity are applied by the drive-train model, which carries those masses.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.loads.rotor import Turbine

N_AZIMUTH = 16
LOAD_COLUMNS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def grid_points(turbine: Turbine) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotor-plane grid: (y, z) of the hub centre then ``N_AZIMUTH`` points on each station ring [m].

    Returns the points (1 + n_r N_AZIMUTH, 2) and the grid azimuths [rad].
    """
    r, _ = turbine.stations
    az = 2.0 * np.pi * np.arange(N_AZIMUTH) / N_AZIMUTH
    rr, aa = np.meshgrid(r, az, indexing="ij")
    pts = np.column_stack([-rr.ravel() * np.sin(aa.ravel()), rr.ravel() * np.cos(aa.ravel())])
    return np.vstack([[0.0, 0.0], pts]), az


def inflow_in_shaft_frame(turbine: Turbine, wind_speed: float, shear_exponent: float,
                          inclination_deg: float, fluct: NDArray[np.float64],
                          z_points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Wind velocity at the grid points in the shaft frame, shape (3, n_t, n_pts) [m/s].

    ``fluct`` holds the turbulent u, v, w (3, n_t, n_pts) along, across and normal to the mean
    (inclined) flow; the mean speed follows the power law ``V (z / z_hub)^alpha``.
    """
    chi, tau = np.deg2rad(inclination_deg), np.deg2rad(turbine.tilt_deg)
    height = np.maximum(turbine.hub_height + z_points, 1.0)
    mean = wind_speed * (height / turbine.hub_height) ** shear_exponent
    # ground frame: mean flow along (cos chi, 0, sin chi); w along (-sin chi, 0, cos chi);
    # shaft frame: X = (cos tau, 0, -sin tau), Z = (sin tau, 0, cos tau). Composed, X and Z turn
    # the (along, w) pair by chi + tau: written into one array without whole-field temporaries
    out = np.empty_like(fluct)
    c, s = np.cos(chi + tau), np.sin(chi + tau)
    along = np.add(fluct[0], mean[None, :], out=out[1])      # out[1] as scratch, overwritten below
    np.multiply(along, c, out=out[0])
    out[0] -= s * fluct[2]
    np.multiply(along, s, out=out[2])
    out[2] += c * fluct[2]
    out[1] = fluct[1]
    return out


@njit(cache=True)
def _simulate(inflow: NDArray[np.float64], spinup: int, n_az: int, dt: float, radius: NDArray[np.float64],
              area: NDArray[np.float64], big_r: float, rho: float, inertia: float,
              tsr: NDArray[np.float64], pitch: NDArray[np.float64], ct: NDArray[np.float64],
              cq: NDArray[np.float64], law: NDArray[np.float64], omega0: float, beta0: float,
              ctl: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Time loop: rotor speed, azimuth, pitch PI and element loads over ``spinup`` steps taken from
    the end of the (periodic) inflow, then the whole record. Returns (spinup + n_t, 10).

    The inflow (3, n_t, n_pts) is read in place: ring j, grid azimuth i is point ``1 + j n_az + i``."""
    n_t = inflow.shape[1]
    n_r = radius.size
    out = np.empty((spinup + n_t, 10))
    omega, psi, beta = omega0, 0.0, beta0
    integ = ctl[6]
    for n in range(spinup + n_t):
        ti = (n_t - spinup + n) % n_t
        fx = fy = fz = mx = my = mz = 0.0
        for b in range(3):
            az = psi + 2.0 * np.pi * b / 3.0
            pos = (az / (2.0 * np.pi)) % 1.0 * n_az
            i0 = int(pos) % n_az
            i1 = (i0 + 1) % n_az
            t = pos - int(pos)
            c, s = np.cos(az), np.sin(az)
            for j in range(n_r):
                p0, p1 = 1 + j * n_az + i0, 1 + j * n_az + i1
                ux = (1 - t) * inflow[0, ti, p0] + t * inflow[0, ti, p1]
                uy = (1 - t) * inflow[1, ti, p0] + t * inflow[1, ti, p1]
                uz = (1 - t) * inflow[2, ti, p0] + t * inflow[2, ti, p1]
                ux = max(ux, 0.1)
                w_t = omega * radius[j] + uy * c + uz * s
                lam = w_t * big_r / (radius[j] * ux)
                q = 0.5 * rho * ux * ux * area[j]
                i, k, tx, ty = _cell(tsr, pitch, lam, beta)
                dt_ = q * _blend(ct, i, k, tx, ty)
                dq = q * big_r * _blend(cq, i, k, tx, ty)
                ft = dq / radius[j]
                fx += dt_
                fy -= ft * c
                fz -= ft * s
                mx += dq
                my += radius[j] * dt_ * c
                mz += radius[j] * dt_ * s
        q_gen, beta, integ = controller_step(omega, beta, integ, dt, law, ctl)
        omega, psi = record_and_step(out, n, fx, fy, fz, mx, my, mz, omega, beta, q_gen, psi, dt, inertia)
    return out


@njit(cache=True)
def record_and_step(out: NDArray[np.float64], n: int, fx: float, fy: float, fz: float, mx: float, my: float,
                    mz: float, omega: float, beta: float, q_gen: float, psi: float, dt: float,
                    inertia: float) -> tuple[float, float]:  # pragma: no cover - compiled
    """Write step ``n`` of a rotor loop (hub forces [N] and moments [N m], rotor speed [rad/s],
    pitch [rad], generator torque [N m], azimuth [rad]) into ``out`` and advance the drive-train's
    one rotational degree of freedom by explicit Euler: the rotor speed and azimuth of step ``n + 1``."""
    out[n, 0], out[n, 1], out[n, 2] = fx, fy, fz
    out[n, 3], out[n, 4], out[n, 5] = mx, my, mz
    out[n, 6], out[n, 7], out[n, 8], out[n, 9] = omega, beta, q_gen, psi
    omega += dt * (mx - q_gen) / inertia
    return omega, psi + dt * omega


@njit(cache=True)
def controller_step(omega: float, beta: float, integ: float, dt: float, law: NDArray[np.float64],
                    ctl: NDArray[np.float64]) -> tuple[float, float, float]:  # pragma: no cover (compiled)
    """One controller step at rotor speed ``omega`` [rad/s]: generator torque demand (the torque law
    ``law``, rated torque once pitching) and the gain-scheduled PI pitch within its rate limit.
    ``ctl`` holds rated speed, rated torque, K_P, K_I, gain knee, pitch rate, the integrator's start
    and the largest pitch (:func:`torque_law`). Returns torque [N m], pitch [rad], integrator [rad s]."""
    rated_speed, rated_torque, kp, ki, knee, rate, beta_max = ctl[0], ctl[1], ctl[2], ctl[3], ctl[4], ctl[5], ctl[7]
    if beta >= 0.0175:
        q_gen = rated_torque
    else:
        q_gen = np.interp(omega, law[0], law[1])
    err = omega - rated_speed
    gk = 1.0 / (1.0 + beta / knee)
    integ = min(max(integ + err * dt, 0.0), beta_max / (gk * ki))
    cmd = min(max(gk * (kp * err + ki * integ), 0.0), beta_max)
    beta += min(max(cmd - beta, -rate * dt), rate * dt)
    return q_gen, beta, integ


def torque_law(turbine: Turbine, beta0: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The controller's tabulated torque law (2, 2001) and its constants for :func:`controller_step`,
    the PI integrator set to hold pitch ``beta0`` [rad]."""
    w_tab = np.linspace(0.0, 1.5 * turbine.rated_speed, 2001)
    gk0 = 1.0 / (1.0 + beta0 / turbine.gain_knee)
    integ = beta0 / (gk0 * turbine.ki) if turbine.ki > 0 else 0.0
    ctl = np.array([turbine.rated_speed, turbine.rated_torque, turbine.kp, turbine.ki, turbine.gain_knee,
                    turbine.pitch_rate, integ, float(turbine.table.pitch[-1])])
    return np.vstack([w_tab, turbine.generator_torque(w_tab)]), ctl


@njit(cache=True)
def _cell(x: NDArray[np.float64], y: NDArray[np.float64], xq: float,
          yq: float) -> tuple[int, int, float, float]:  # pragma: no cover (compiled)
    """Grid cell ``(i, j)`` of ``(xq, yq)`` and its fractions ``(tx, ty)``, clamped to the grid (the rule of
    ``rotor.bilinear``; the thrust and torque tables share the grid, so one search serves both)."""
    xq = min(max(xq, x[0]), x[-1])
    yq = min(max(yq, y[0]), y[-1])
    i = min(max(np.searchsorted(x, xq) - 1, 0), x.size - 2)
    j = min(max(np.searchsorted(y, yq) - 1, 0), y.size - 2)
    return i, j, (xq - x[i]) / (x[i + 1] - x[i]), (yq - y[j]) / (y[j + 1] - y[j])


@njit(cache=True)
def _blend(table: NDArray[np.float64], i: int, j: int, tx: float, ty: float) -> float:  # pragma: no cover
    """Bilinear value of ``table`` in cell ``(i, j)`` at fractions ``(tx, ty)``."""
    return ((1 - tx) * (1 - ty) * table[i, j] + tx * (1 - ty) * table[i + 1, j]
            + (1 - tx) * ty * table[i, j + 1] + tx * ty * table[i + 1, j + 1])


def simulate_rotor(turbine: Turbine, inflow: NDArray[np.float64], dt: float,
                   initial: dict[str, float], spinup: int = 0) -> NDArray[np.float64]:
    """Run the rotor/controller loop over the inflow on the grid.

    Parameters
    ----------
    inflow : ndarray (3, n_t, n_pts)
        Shaft-frame wind at :func:`grid_points` (hub centre first) [m/s].
    initial : dict
        Steady operating point (``rotor_speed`` [rad/s], ``pitch`` [rad]) to start from.
    spinup : int
        Steps run first over the last ``spinup`` samples of the inflow (a periodic record wraps
        around) and discarded, so the record starts from a settled rotor and controller.

    Returns
    -------
    ndarray (n_t, 10)
        Fx, Fy, Fz [N], Mx, My, Mz [N m], rotor speed [rad/s], pitch [rad], generator torque
        [N m], azimuth of blade 1 [rad].
    """
    r, area = turbine.stations
    spinup = min(int(spinup), inflow.shape[1])
    law, ctl = torque_law(turbine, initial["pitch"])
    tab = turbine.table
    out = _simulate(np.ascontiguousarray(inflow), spinup, N_AZIMUTH, dt, r, area, turbine.rotor_radius,
                    turbine.air_density, turbine.rotor_inertia, tab.tsr, tab.pitch, tab.ct,
                    np.ascontiguousarray(tab.cq), law, initial["rotor_speed"], initial["pitch"], ctl)
    return out[spinup:]

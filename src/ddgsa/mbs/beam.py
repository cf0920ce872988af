"""Finite-element shaft: eigenmodes used as FFR shape functions (seed 000 §2.5).

A shaft of length L on the x axis, meshed by :func:`mesh`, carrying point masses and
rotary inertias at its nodes. Three independent fields:

- bending (one transverse plane; the shaft is axisymmetric, so Y and Z share the shapes):
  Euler-Bernoulli Hermite cubic elements, nodal (w, w'), consistent mass, pinned supports
  (w = 0) at the bearing nodes; with ``BeamSpec.shear_stiffness`` set, Timoshenko elements
  instead (shear deformation and the shaft's rotary inertia; nodal (w, psi), psi the section
  rotation; Friedman and Kosmatka's interdependent interpolation, exact for a uniform static
  element), which tend to the Euler-Bernoulli element as the shear stiffness grows;
- axial: linear bar elements, u = 0 at the axial (front) bearing, or free with a longitudinal
  spring there (``axial_spring``, seed 000 §2.5);
- torsion: linear elements, free-free (the spin is the body's rigid rotation).

Modes are mass-normalised by the solver and then scaled so the largest nodal displacement
(or twist) is 1, so elastic coordinates carry metres (radians for torsion).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import eigh


BEAMS = ("euler_bernoulli", "timoshenko")
"""The bending element families a model may build its shafts from (:class:`BeamSpec` ``shear_stiffness``)."""


@dataclass(frozen=True)
class BeamSpec:
    """Geometry, stiffness and attached inertias of a shaft (SI units).

    Attributes
    ----------
    nodes : tuple of float
        Node positions from 0 to the shaft length [m], ascending (bearing and end-inertia
        positions must be nodes; see :func:`mesh`).
    mass : float
        Shaft mass [kg], uniformly distributed.
    polar_inertia : float
        Shaft polar mass moment of inertia about its axis [kg m^2].
    EI, EA, GJ : float
        Bending [N m^2], axial [N] and torsional [N m^2] stiffness.
    end_masses : tuple of (x, mass, J_axial, J_diametral)
        Rigid inertias attached at nodes [m, kg, kg m^2, kg m^2].
    supports : tuple of float
        Positions of the bending supports (bearings) [m].
    axial_support : float
        Position where the axial field is held (the axial bearing) [m].
    axial_spring : float, optional
        Axial stiffness of that bearing [N/m]: the field is then free, on this spring, and its
        first mode is the shaft bouncing on the spring (None: held rigidly). The spring shapes
        the modes only; the generalised stiffness ``k_axial`` is the shaft's own (a body puts
        the bearing in as an element).
    shear_stiffness : float, optional
        Shear stiffness ``kappa G A`` of the section [N]: Timoshenko bending elements with the
        shaft's rotary inertia (``polar_inertia / 2`` per unit length, a circular section's
        diametral inertia); None: Euler-Bernoulli elements without it.
    """

    nodes: tuple[float, ...]
    mass: float
    polar_inertia: float
    EI: float
    EA: float
    GJ: float
    end_masses: tuple[tuple[float, float, float, float], ...]
    supports: tuple[float, ...]
    axial_support: float
    axial_spring: float | None = None
    shear_stiffness: float | None = None

    @property
    def x(self) -> NDArray[np.float64]:
        """Node positions [m]."""
        return np.asarray(self.nodes)

    @property
    def length(self) -> float:
        """Shaft length [m]."""
        return float(self.nodes[-1])

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return len(self.nodes) - 1

    def node_index(self, x: float) -> int:
        """Index of the node at ``x`` (raises if ``x`` is not on a node)."""
        i = int(np.argmin(np.abs(self.x - x)))
        if abs(self.x[i] - x) > 1e-9 * max(1.0, self.length):
            raise ValueError(f"position {x} m is not a node of the shaft mesh")
        return i


def mesh(breakpoints: list[float], max_element: float) -> tuple[float, ...]:
    """Nodes through all ``breakpoints`` (sorted, from 0 to L) with elements no longer than ``max_element``."""
    pts = sorted(set(float(b) for b in breakpoints))
    nodes = [pts[0]]
    for a, b in zip(pts[:-1], pts[1:]):
        k = max(1, int(np.ceil((b - a) / max_element - 1e-9)))
        nodes += list(np.linspace(a, b, k + 1)[1:])
    return tuple(nodes)


def _scatter(elements: NDArray[np.float64], dofs_per_node: int, n_nodes: int) -> NDArray[np.float64]:
    """Global matrix of a chain of two-node elements: ``elements`` (n_e, 2 d, 2 d), element e on the
    DOFs ``d e .. d e + 2 d - 1``."""
    size = dofs_per_node * n_nodes
    out = np.zeros((size, size))
    local = np.arange(elements.shape[1])
    for first in (0, 1):            # every other element: their blocks do not overlap, so no index repeats
        start = dofs_per_node * np.arange(first, elements.shape[0], 2)[:, None, None]
        out[start + local[:, None], start + local[None, :]] += elements[first::2]
    return out


_K_HERMITE = np.array([[[12, 0, -12, 0], [0, 0, 0, 0], [-12, 0, 12, 0], [0, 0, 0, 0]],
                       [[0, 6, 0, 6], [6, 0, -6, 0], [0, -6, 0, -6], [6, 0, -6, 0]],
                       [[0, 0, 0, 0], [0, 4, 0, 2], [0, 0, 0, 0], [0, 2, 0, 4]]], dtype=float)
_M_HERMITE = np.array([[[156, 0, 54, 0], [0, 0, 0, 0], [54, 0, 156, 0], [0, 0, 0, 0]],
                       [[0, 22, 0, -13], [22, 0, 13, 0], [0, 13, 0, -22], [-13, 0, -22, 0]],
                       [[0, 0, 0, 0], [0, 4, 0, -3], [0, 0, 0, 0], [0, -3, 0, 4]]], dtype=float)
"""Euler-Bernoulli Hermite element (nodal w, w'): stiffness ``EI / le^3 [[12, 6 le, -12, 6 le], ...]`` and
consistent mass ``rho A le / 420 [[156, 22 le, 54, -13 le], ...]``, split by powers of ``le``."""


def shear_coefficient(poisson: float, inner_ratio: float = 0.0) -> float:
    """Timoshenko shear coefficient ``kappa`` of a circular tube (Cowper, J. Appl. Mech. 33, 1966).

    ``6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2)`` for Poisson's ratio
    ``nu`` [-] and bore-to-outer radius ratio ``m`` [-] (0: solid, 0.886 at nu = 0.3).
    """
    m2 = inner_ratio * inner_ratio
    r12 = (1.0 + m2) ** 2
    return 6.0 * (1.0 + poisson) * r12 / ((7.0 + 6.0 * poisson) * r12 + (20.0 + 12.0 * poisson) * m2)


def timoshenko_element(ei: float, shear: float, rho_a: float, rho_i: float,
                       le: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Stiffness and consistent mass (translational plus rotary) of a Timoshenko element, nodal (w, psi).

    Friedman and Kosmatka (Computers & Structures 47, 1993) with ``phi = 12 EI / (kappa G A le^2)``;
    ``phi = 0`` is the Euler-Bernoulli Hermite element (plus the rotary term ``rho_i``).

    Parameters
    ----------
    ei : bending stiffness [N m^2]; ``shear`` : kappa G A [N]
    rho_a : mass per unit length [kg/m]; ``rho_i`` : diametral inertia per unit length [kg m]
    le : element length [m]
    """
    p, L = 12.0 * ei / (shear * le * le), le
    c = ei / ((1.0 + p) * L ** 3)
    k = c * np.array([[12.0, 6 * L, -12.0, 6 * L],
                      [6 * L, (4 + p) * L * L, -6 * L, (2 - p) * L * L],
                      [-12.0, -6 * L, 12.0, -6 * L],
                      [6 * L, (2 - p) * L * L, -6 * L, (4 + p) * L * L]])
    a11, a13 = 13 / 35 + 7 * p / 10 + p * p / 3, 9 / 70 + 3 * p / 10 + p * p / 6
    a12, a14 = (11 / 210 + 11 * p / 120 + p * p / 24) * L, -(13 / 420 + 3 * p / 40 + p * p / 24) * L
    a22, a24 = (1 / 105 + p / 60 + p * p / 120) * L * L, -(1 / 140 + p / 60 + p * p / 120) * L * L
    mt = np.array([[a11, a12, a13, a14], [a12, a22, -a14, a24], [a13, -a14, a11, -a12], [a14, a24, -a12, a22]])
    b12, b22, b24 = (0.1 - p / 2) * L, (2 / 15 + p / 6 + p * p / 3) * L * L, (-1 / 30 - p / 6 + p * p / 6) * L * L
    mr = np.array([[1.2, b12, -1.2, b12], [b12, b22, -b12, b24], [-1.2, -b12, 1.2, -b12], [b12, b24, -b12, b22]])
    m = rho_a * L / (1 + p) ** 2 * mt + rho_i / ((1 + p) ** 2 * L) * mr
    return k, m


def bending_matrices(spec: BeamSpec) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Global bending stiffness and consistent mass (nodal w and slope or section rotation), end inertias included."""
    n = spec.n_elements + 1
    rho_a = spec.mass / spec.length
    le = np.diff(spec.x)[:, None, None]
    if spec.shear_stiffness is None:
        # Hermite element matrices as powers of the element length: k_e = EI sum_p le^(p-3) K_p, m_e = rho A le / 420 sum_p le^p M_p
        k_e = spec.EI * (_K_HERMITE[0] / le ** 3 + _K_HERMITE[1] / le ** 2 + _K_HERMITE[2] / le)
        m_e = rho_a * le / 420 * (_M_HERMITE[0] + _M_HERMITE[1] * le + _M_HERMITE[2] * le ** 2)
    else:
        rho_i = 0.5 * spec.polar_inertia / spec.length
        pairs = [timoshenko_element(spec.EI, spec.shear_stiffness, rho_a, rho_i, float(h)) for h in le[:, 0, 0]]
        k_e, m_e = np.array([kp for kp, _ in pairs]), np.array([mp for _, mp in pairs])
    k, m = _scatter(k_e, 2, n), _scatter(m_e, 2, n)
    for x, mass, _, j_diam in spec.end_masses:
        i = spec.node_index(x)
        m[2 * i, 2 * i] += mass
        m[2 * i + 1, 2 * i + 1] += j_diam
    return k, m


def bar_matrices(spec: BeamSpec, stiffness: float, line_inertia: float,
                 end_index: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Linear-element stiffness and consistent mass of an axial (end_index 1) or torsion (2) field."""
    n = spec.n_elements + 1
    le = np.diff(spec.x)[:, None, None]
    k = _scatter(stiffness / le * np.array([[1.0, -1.0], [-1.0, 1.0]]), 1, n)
    m = _scatter(line_inertia * le / 6 * np.array([[2.0, 1.0], [1.0, 2.0]]), 1, n)
    for end in spec.end_masses:
        i = spec.node_index(end[0])
        m[i, i] += end[end_index]
    return k, m


@dataclass(frozen=True)
class ShaftModes:
    """Shape functions at the shaft nodes and their elastic stiffness.

    Attributes
    ----------
    x : ndarray (n_nodes,)
        Node positions [m].
    axial : ndarray (n_ax, n_nodes)
        Axial displacement shapes [-].
    torsion : ndarray (n_to, n_nodes)
        Twist shapes [rad per unit coordinate].
    bending, bending_slope : ndarray (n_be, n_nodes)
        Transverse displacement [-] and slope (Timoshenko: section rotation) [1/m] shapes (same in Y and Z).
    k_axial, k_torsion, k_bending : ndarray
        Diagonal generalised stiffnesses of each field [N/m, N m/rad, N/m].
    freq_axial, freq_torsion, freq_bending : ndarray
        Natural frequencies of the retained modes of the FE model [Hz].
    """

    x: NDArray[np.float64]
    axial: NDArray[np.float64]
    torsion: NDArray[np.float64]
    bending: NDArray[np.float64]
    bending_slope: NDArray[np.float64]
    k_axial: NDArray[np.float64]
    k_torsion: NDArray[np.float64]
    k_bending: NDArray[np.float64]
    freq_axial: NDArray[np.float64]
    freq_torsion: NDArray[np.float64]
    freq_bending: NDArray[np.float64]


def _modes(k: NDArray[np.float64], m: NDArray[np.float64], free: NDArray[np.intp], count: int,
           skip_rigid: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest ``count`` eigenpairs on the free DOFs (optionally skipping the one rigid-body mode)."""
    start = 1 if skip_rigid else 0
    w2, vec = eigh(k[np.ix_(free, free)], m[np.ix_(free, free)], subset_by_index=[start, start + count - 1])
    full = np.zeros((k.shape[0], count))
    full[free] = vec
    return np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi), full


def shaft_modes(spec: BeamSpec, n_axial: int = 1, n_torsion: int = 1, n_bending: int = 2) -> ShaftModes:
    """Eigenmodes of the shaft fields, scaled to unit peak, with their generalised stiffness."""
    n = spec.n_elements + 1
    kb, mb = bending_matrices(spec)
    pinned = {2 * spec.node_index(x) for x in spec.supports}
    free_b = np.array([i for i in range(2 * n) if i not in pinned])
    fb, vb = _modes(kb, mb, free_b, n_bending)
    ka, ma = bar_matrices(spec, spec.EA, spec.mass / spec.length, 1)
    i_ax = spec.node_index(spec.axial_support)
    ka_bc = ka.copy()
    if spec.axial_spring is None:
        free_a = np.array([i for i in range(n) if i != i_ax])
    else:
        ka_bc[i_ax, i_ax] += spec.axial_spring
        free_a = np.arange(n)
    fa, va = _modes(ka_bc, ma, free_a, n_axial)
    kt, mt = bar_matrices(spec, spec.GJ, spec.polar_inertia / spec.length, 2)
    ft, vt = _modes(kt, mt, np.arange(n), n_torsion, skip_rigid=True)

    def unit(v: NDArray[np.float64], peak_rows: slice) -> NDArray[np.float64]:
        scale = v[peak_rows][np.argmax(np.abs(v[peak_rows]), axis=0), np.arange(v.shape[1])]
        return v / scale

    vb = unit(vb, slice(0, None, 2))
    va, vt = unit(va, slice(None)), unit(vt, slice(None))
    return ShaftModes(
        x=spec.x, axial=va.T, torsion=vt.T, bending=vb[0::2].T, bending_slope=vb[1::2].T,
        k_axial=np.diag(va.T @ ka @ va), k_torsion=np.diag(vt.T @ kt @ vt), k_bending=np.diag(vb.T @ kb @ vb),
        freq_axial=fa, freq_torsion=ft, freq_bending=fb)

"""Several sensors as one: Fisher's discriminant trained and scored on halves of the points,
and a greedy choice of sensors validated on points that took no part in it."""


from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray


from ddgsa.detection.single import (COMBINED, Detection, DetectionError, DetectionSettings, Seed, _pairs, _refused, _rng,
                                    _seq, _verdict, detect, layout)


def _fisher(xh: NDArray[np.float64], xf: NDArray[np.float64], wh: NDArray[np.float64],
            wf: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Centre, scale and weights ``w = S^+ (mu_f - mu_h)`` of Fisher's discriminant on weighted measurements."""
    def moments(x: NDArray[np.float64], w: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        mu = (w @ x) / w.sum()
        d = x - mu
        return mu, (d * w[:, None]).T @ d
    mh, ch = moments(xh, wh)
    centre, scale = mh, np.sqrt(np.diag(ch) / max(wh.sum() - 1, 1.0))
    scale = np.where(scale > 0, scale, 1.0)
    mf, cf = moments(xf, wf)
    pooled = (ch + cf) / np.outer(scale, scale) / max(wh.sum() + wf.sum() - 2, 1.0)
    if not (np.isfinite(pooled).all() and np.isfinite(mf).all()):       # a population with no weight: no direction
        return centre, scale, np.full(len(scale), np.nan)
    return centre, scale, np.linalg.pinv(np.atleast_2d(pooled), rtol=1e-10) @ ((mf - mh) / scale)


def fisher_scores(healthy: NDArray[np.float64], faulty: NDArray[np.float64], seed: Seed = 0,
                  units_healthy: ArrayLike | None = None, units_faulty: ArrayLike | None = None,
                  weights: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Held-out scores of Fisher's linear discriminant, two-fold.

    The parameter points (every measurement its own when no units are given) are split at random
    into halves A and B, a point shared by both populations going to one half; the discriminant
    ``w = S^+ (mu_f - mu_h)`` of the standardised sensors (``S`` the pooled within-population
    covariance, pseudo-inverse for collinear sensors) is trained on A and scores B, and the other
    way round. Faulty scores tend to be larger.

    Parameters
    ----------
    healthy, faulty : ndarray, shape (n, n_sensors)
        Finite measurements.
    seed : int or SeedSequence
        Seed of the split.
    units_healthy, units_faulty : array_like, optional
        Units of the measurements (:func:`layout`).
    weights : tuple of ndarray, optional
        Multiplicities of the measurements in training (a bootstrap re-draw); default 1.

    Returns
    -------
    tuple of ndarray
        Held-out scores of every healthy and every faulty measurement [-].
    """
    lay = layout(units_healthy, units_faulty, len(healthy), len(faulty))
    n_points = int(max(lay.point_h.max(), lay.point_f.max())) + 1
    half = _rng(seed).permutation(n_points) % 2
    in_h, in_f = half[lay.point_h], half[lay.point_f]
    wh, wf = weights if weights is not None else (np.ones(len(healthy)), np.ones(len(faulty)))
    out_h, out_f = np.empty(len(healthy)), np.empty(len(faulty))
    for train in (0, 1):
        th, tf = in_h == train, in_f == train
        centre, scale, w = _fisher(healthy[th], faulty[tf], wh[th], wf[tf])
        out_h[~th] = ((healthy[~th] - centre) / scale) @ w
        out_f[~tf] = ((faulty[~tf] - centre) / scale) @ w
    return out_h, out_f


def detect_combined(healthy: ArrayLike, faulty: ArrayLike, settings: DetectionSettings | None = None,
                    seed: Seed = 0, units_healthy: ArrayLike | None = None,
                    units_faulty: ArrayLike | None = None) -> Detection:
    """Detection statistics of the multi-sensor detector (:func:`fisher_scores`, alarm above).

    The interval includes the training's variability: each bootstrap re-draw trains the
    discriminant again on the re-drawn measurements (``settings.bootstrap // 5`` re-draws, at
    least 100) before its held-out scores are counted.

    Parameters
    ----------
    healthy, faulty : array_like, shape (n, n_sensors)
        Measurements of every sensor; a row with any non-finite entry refuses the verdict.
    settings, seed, units_healthy, units_faulty
        As in :func:`detect` (``seed`` also splits the halves).
    """
    h, f = np.atleast_2d(np.asarray(healthy, dtype=float)), np.atleast_2d(np.asarray(faulty, dtype=float))
    if h.shape[1] != f.shape[1] or h.shape[1] < 2:
        raise DetectionError(f"the combined detector needs >= 2 sensors in both populations, got {h.shape[1]} "
                             f"and {f.shape[1]}")
    ok_h, ok_f = np.isfinite(h).all(axis=1), np.isfinite(f).all(axis=1)
    if not (ok_h.all() and ok_f.all()):
        return _refused(Detection(COMBINED, len(h), len(f)),
                        f"{int((~ok_h).sum())} of {len(h)} healthy and {int((~ok_f).sum())} of {len(f)} faulty "
                        "measurements failed or are not finite in some sensor")
    return _combined(h, f, settings, seed, units_healthy, units_faulty)[0]


def _combined(h: NDArray[np.float64], f: NDArray[np.float64], settings: DetectionSettings | None, seed: Seed,
              units_h: ArrayLike | None, units_f: ArrayLike | None
              ) -> tuple[Detection, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    s = settings or DetectionSettings()
    split, boot = _seq(seed).spawn(2)
    sh, sf = fisher_scores(h, f, split, units_h, units_f)
    point = detect(sh, sf, COMBINED, s, boot, units_h, units_f, direction=1)
    if point.detectable is None and not np.isfinite(point.pod):
        return point, (sh, sf)
    lay = layout(units_h, units_f, len(h), len(f))
    n_boot = max(100, s.bootstrap // 5)
    wh, wf = lay.weights(n_boot, _rng(boot))
    reps = np.empty((n_boot, 3))
    for b in range(n_boot):
        with np.errstate(invalid="ignore", divide="ignore"):
            bh, bf = fisher_scores(h, f, split, units_h, units_f, (wh[b].astype(float), wf[b].astype(float)))
        ok = np.isfinite(bh).all() and np.isfinite(bf).all()      # a re-draw that misses a training half: none
        reps[b] = _pairs(bh, bf, lay).stats(wh[b:b + 1], wf[b:b + 1], s.false_alarm, False)[0] if ok else np.nan
    ones = _pairs(sh, sf, lay).stats(np.ones((1, len(h)), np.float32), np.ones((1, len(f)), np.float32),
                                        s.false_alarm)[0]
    moments = {"mean_healthy": point.mean_healthy, "mean_faulty": point.mean_faulty, "std_healthy": point.std_healthy}
    d = _verdict(Detection(COMBINED, len(h), len(f)), moments, 1, point.threshold, ones, reps, sh, sf, lay, wh, wf, s)
    return d, (sh, sf)


def select_sensors(healthy: pd.DataFrame, faulty: pd.DataFrame, settings: DetectionSettings | None = None,
                   seed: Seed = 0, units_healthy: ArrayLike | None = None, units_faulty: ArrayLike | None = None,
                   min_gain: float = 0.005) -> dict[str, Any]:
    """Greedy forward choice of the combined detector's sensors, validated on held-out points.

    The parameter points are split at random into a selection half and a validation half (a point
    shared by both populations goes to one half). On the selection half, sensors are added one at
    a time, each time the one whose Fisher detector (:func:`fisher_scores`, two-fold within the
    half) has the highest held-out AUC (over pairs sharing no unit), while the AUC grows by at least
    ``min_gain``. The chosen set and, for reference, all sensors are then trained on the whole
    selection half and scored on the validation half, which took no part in the choice: those
    statistics (:func:`detect`, with intervals) say what the choice is worth on new turbines.

    Parameters
    ----------
    healthy, faulty : DataFrame
        Finite measurements, one column per candidate sensor (>= 2).
    settings, seed, units_healthy, units_faulty
        As in :func:`detect`.
    min_gain : float
        Smallest AUC gain that adds a sensor [-].

    Returns
    -------
    dict
        ``sensors`` (chosen, in order), ``path`` (selection AUC after each addition) and
        ``validation`` / ``validation_all`` (:class:`Detection` of the chosen and of all sensors on
        the validation half).
    """
    s = settings or DetectionSettings()
    names = list(healthy.columns)
    if len(names) < 2:
        raise DetectionError(f"sensor selection needs >= 2 candidate sensors, got {names}")
    h, f = healthy.to_numpy(float), faulty.to_numpy(float)
    lay = layout(units_healthy, units_faulty, len(h), len(f))
    uh = np.column_stack([lay.point_h, lay.real_h]) if units_healthy is not None else None
    uf = np.column_stack([lay.point_f, lay.real_f]) if units_faulty is not None else None
    split, inner, boot = _seq(seed).spawn(3)
    half = _rng(split).permutation(int(max(lay.point_h.max(), lay.point_f.max())) + 1) % 2
    sel_h, sel_f = half[lay.point_h] == 0, half[lay.point_f] == 0
    sub = (lambda u, m: None if u is None else u[m])
    ones = (np.ones((1, int(sel_h.sum())), np.float32), np.ones((1, int(sel_f.sum())), np.float32))
    lay_sel = layout(sub(uh, sel_h), sub(uf, sel_f), int(sel_h.sum()), int(sel_f.sum()))

    def auc(cols: list[int]) -> float:
        sh, sf = fisher_scores(h[sel_h][:, cols], f[sel_f][:, cols], inner, sub(uh, sel_h), sub(uf, sel_f))
        return float(_pairs(sh, sf, lay_sel).stats(*ones, s.false_alarm, False)[0, 0])

    chosen: list[int] = []
    path: list[float] = []
    while len(chosen) < len(names):
        score, best = max((auc(chosen + [j]), j) for j in range(len(names)) if j not in chosen)
        if path and score < path[-1] + min_gain:
            break
        chosen.append(best)
        path.append(score)

    def validate(cols: list[int], out: str) -> Detection:
        centre, scale, w = _fisher(h[sel_h][:, cols], f[sel_f][:, cols], np.ones(int(sel_h.sum())),
                                   np.ones(int(sel_f.sum())))
        vh, vf = ((x[~m][:, cols] - centre) / scale @ w for x, m in ((h, sel_h), (f, sel_f)))
        return detect(vh, vf, out, s, boot, sub(uh, ~sel_h), sub(uf, ~sel_f), direction=1)

    return {"sensors": [names[j] for j in chosen], "path": path,
            "validation": validate(chosen, "selected"), "validation_all": validate(list(range(len(names))), "all")}


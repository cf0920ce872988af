"""Fault detectability as condition monitoring measures it: detection against false alarms.

Model-agnostic statistics on two populations of measurements of one or more sensors
(outputs): *healthy* and *faulty*. Each measurement is one value (one wind record of one
parameter point plus measurement noise), never an average. Measurements rest on *units*
(:func:`layout`): the parameter point (turbine) and the wind record(s). A study evaluates every
fault level on the same points and records (common random numbers), so a faulty value and its
healthy twin share both; a monitoring system never compares those. Every statistic therefore
compares only measurements that share **no** unit (an exact estimator for independent draws),
and every interval re-draws whole units. For one sensor the detector raises an alarm when a
measurement passes a threshold set on healthy measurements:

- **threshold** ``t``: the smallest healthy order statistic with at most ``alpha`` of the healthy
  measurements beyond it (a tie with ``t`` does not alarm, so a cluster of equal values never
  passes at once);
- **false-alarm rate**, measured out of sample: each healthy measurement against the threshold
  of the healthy measurements it shares no unit with;
- **probability of detection** ``POD``: each faulty measurement against the threshold of the
  healthy measurements it shares no unit with;
- **ROC AUC** ``P(faulty beyond healthy)`` (Mann-Whitney over the pairs that share no unit, ties
  count one half);
- **intervals**: a two-way (pigeonhole) bootstrap re-draws points and records independently
  (each within the units of the healthy population, the faulty, or both); the percentile
  half-widths are widened by ``t_(G-1)/z sqrt(G/(G-1))`` for ``G`` effective units, and joined with
  a Clopper-Pearson interval on the effective count (POD: ``G`` measurements; AUC:
  ``3 G_h G_f / (G_h + G_f)``, the count whose binomial variance is Mann-Whitney's at 1/2);
- **effective size** ``G``: independent measurements worth the same, var(ranks) over the
  bootstrap variance of their mean, less one for the bootstrap's ``(G - 1)/G`` (a population
  resting on 4 records that dominate is worth about 4);
- **effect size** ``|mean_f - mean_h| / std_h``.

The side of the threshold (``direction``: +1 alarms above, -1 below) is the side the faulty
population lies on (AUC >= 1/2). A sensor is ``detectable`` when the lower end of the POD
interval reaches the POD target; a verdict is refused (``None``, with a reason) when any
measurement failed or is not finite, when the healthy population has zero spread, or when it
cannot resolve the false-alarm rate: fewer than ``1/alpha`` measurements, or an effective size
below ``1/alpha`` ("4 realisations: POD resolution 0.25; add realisations").

Several sensors are combined by Fisher's linear discriminant ``w = S^+ (mu_f - mu_h)``
(``S`` the pooled covariance of the standardised sensors) trained on one half of the points
and scored on the other, and vice versa; the held-out scores are then one sensor to the
statistics above, and their interval re-trains the discriminant on every bootstrap re-draw
(training variability). :func:`select_sensors` chooses a subset greedily and validates it on
points that took no part in the choice.

For Gaussian populations ``N(0, sigma^2)`` and ``N(Delta, sigma^2)``:
``POD = Phi(Delta/sigma - z_(1-alpha))`` and ``AUC = Phi(Delta / (sigma sqrt 2))``.

The package is model-agnostic and sits beside :mod:`ddgsa.gsa`: it imports numpy, scipy, pandas and
:mod:`ddgsa.errors` only. :mod:`~ddgsa.detection.single` holds one sensor's statistics,
:mod:`~ddgsa.detection.combined` the discriminant and the choice of sensors on top of it, and
:mod:`~ddgsa.detection.levels` a fault over its levels (what the ``fault`` study kind calls).
"""

from ddgsa.detection.combined import detect_combined, fisher_scores, select_sensors
from ddgsa.detection.levels import FaultDetectability, assess
from ddgsa.detection.single import (COMBINED, Detection, DetectionError, DetectionSettings, add_noise, clopper_pearson,
                                    detect, layout, threshold_at)

__all__ = ["COMBINED", "Detection", "DetectionError", "DetectionSettings", "FaultDetectability", "add_noise", "assess",
           "clopper_pearson", "detect", "detect_combined", "fisher_scores", "layout", "select_sensors", "threshold_at"]

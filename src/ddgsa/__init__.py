"""ddgsa: global sensitivity analysis workbench for wind-turbine drive-train dynamics.

The public API is what ``__all__`` lists; everything else is internal.
"""

from __future__ import annotations

from ddgsa import loads, models
from ddgsa._version import __version__
from ddgsa.errors import DdgsaError, MethodError, ModelError, SceneError, SpaceError, StudyError
from ddgsa.gsa import SobolResult, sobol
from ddgsa.gsa.result import Diagnostic
from ddgsa.gsa.signal import SignalAxis, SignalResult, sobol_signal
from ddgsa.loads.scene import Scene
from ddgsa.gsa.space import Parameter, ParameterSpace


__all__ = [
    "DdgsaError",
    "Diagnostic",
    "MethodError",
    "ModelError",
    "Parameter",
    "ParameterSpace",
    "Scene",
    "SceneError",
    "SignalAxis",
    "SignalResult",
    "SobolResult",
    "SpaceError",
    "StudyError",
    "__version__",
    "loads",
    "models",
    "sobol",
    "sobol_signal",
]

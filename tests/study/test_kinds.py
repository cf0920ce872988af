"""The study kinds (issue 24): one module each behind one interface, each with its own result type."""

from __future__ import annotations

from dataclasses import fields
from typing import get_args

import pandas as pd

from ddgsa.execute.kinds.common import ABSENT, StudyResult
from ddgsa.execute.kinds.fault import FaultResult
from ddgsa.execute.kinds.gsa import GsaResult
from ddgsa.execute.kinds.sweep import SweepResult
from ddgsa.execute.pipeline import KINDS
from ddgsa.study.spec import StudySpec


def _own(cls: type, base: type) -> set[str]:
    return {f.name for f in fields(cls)} - {f.name for f in fields(base)}


def test_every_kind_the_schema_allows_has_one_module_and_nothing_else() -> None:
    assert set(KINDS) == set(get_args(StudySpec.model_fields["kind"].annotation)) == {"gsa", "sweep", "fault"}


def test_each_result_type_holds_only_its_kinds_fields_and_reads_the_others_as_absent() -> None:
    assert _own(SweepResult, StudyResult) == {"sweep"}
    assert _own(GsaResult, StudyResult) == {"results", "moments", "signal_indices", "signal_generalised", "convergence"}
    assert _own(FaultResult, GsaResult) == {"fault", "fault_smallest", "fault_indices", "fault_detection",
                                            "fault_subsets"}
    assert set(ABSENT) == _own(SweepResult, StudyResult) | _own(FaultResult, StudyResult)
    empty = pd.DataFrame()
    sweep = SweepResult(None, empty, empty, empty, {}, sweep=empty)    # type: ignore[arg-type]
    assert sweep.fault is None and sweep.moments is None and tuple(sweep.results) == ()
    gsa = GsaResult(None, empty, empty, empty, {})                     # type: ignore[arg-type]
    assert gsa.sweep is None and gsa.results == [] and gsa.fault_detection == ()
    try:
        gsa.not_a_field  # noqa: B018
    except AttributeError as exc:
        assert "not_a_field" in str(exc)
    else:
        raise AssertionError("an unknown attribute must raise")

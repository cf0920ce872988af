"""Every element, constraint and body kind the four models use has a compiled form (issue 24): each
model's System packs whole, so the compiled evaluator and generalised-alpha run it (a part that
stops packing would send a model back to the Python loop, 10-100x slower, without a test failing)."""

from __future__ import annotations

import pytest

from ddgsa import models
from ddgsa.mbs.compiled import pack
from ddgsa.models.generator_radial import CONFIGS
from ddgsa.models.hss_rig.scenes import RigScene


@pytest.mark.parametrize("fidelity", ["dq", "kloss", "linear"])
@pytest.mark.parametrize("kind", ["startup", "steady", "coastdown"])
def test_the_rig_packs_whole(fidelity: str, kind: str) -> None:
    scene = RigScene(kind, speed_rpm=1500.0, duration=0.6, sample_rate=2000.0,
                     settle=0.05 if kind == "steady" else 0.0)
    system = models.get("hss_rig", fidelity=fidelity).build(None, scene)[0].system
    assert pack(system).n == system.n


@pytest.mark.parametrize("config", CONFIGS)
def test_the_generator_packs_whole(config: str) -> None:
    system = models.get("generator_radial", config=config).build()[0]
    assert pack(system).n == system.n


def test_the_direct_and_geared_drives_pack_whole() -> None:
    direct = models.get("direct_drive", fidelity="flexible").build().kernel
    geared = models.get("indirect_drive", fidelity="flexible").build()[0].system
    for system in (direct, geared):
        assert pack(system).n == system.n

"""Loads shared between processes through files: generated once per realisation, read back equal."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import ddgsa.loads as loads
from ddgsa.loads import Scene, cache

SCENES = [Scene(wind_speed=v, turbulence_intensity=0.1, duration=30.0, seed=s) for v in (8.0, 14.0) for s in (1, 2)]


def _worker(directory: str, order: int) -> list[np.ndarray]:
    """A fresh process: share through ``directory`` and ask for every scene (in a rotated order)."""
    cache.set_directory(directory)
    return [loads.generate(SCENES[(i + order) % len(SCENES)]).to_numpy() for i in range(len(SCENES))]


@pytest.fixture
def shared(tmp_path: Path):
    loads._generate.cache_clear()
    loads._as_array.cache_clear()
    cache.set_directory(tmp_path)
    yield tmp_path
    cache.set_directory(None)
    loads._generate.cache_clear()
    loads._as_array.cache_clear()


def test_each_realisation_is_generated_once_by_concurrent_processes(shared: Path) -> None:
    """Three processes ask for the same four realisations at once: four generations in all (the
    file lock makes the others wait and read), and every process gets identical loads, equal to
    the in-memory path's."""
    with ProcessPoolExecutor(3) as pool:
        got = list(pool.map(_worker, [str(shared)] * 3, [0, 1, 2]))
    counts = cache.generations(shared)
    assert sorted(counts) == sorted(cache.key(s, loads.NREL5MW) for s in SCENES)
    assert set(counts.values()) == {1}
    cache.set_directory(None)
    loads._generate.cache_clear()
    for order, arrays in enumerate(got):
        for i, arr in enumerate(arrays):
            expect = loads.generate(SCENES[(i + order) % len(SCENES)]).to_numpy()
            np.testing.assert_array_equal(arr, expect)


def test_a_cached_realisation_reads_back_with_its_frame(shared: Path) -> None:
    first = loads.generate(SCENES[0])
    loads._generate.cache_clear()                     # the next call reads the file
    again = loads.generate(SCENES[0])
    assert cache.generations(shared) == {cache.key(SCENES[0], loads.NREL5MW): 1}
    assert list(again.columns) == list(first.columns) and again.index.equals(first.index)
    np.testing.assert_array_equal(again.to_numpy(), first.to_numpy())
    assert again.attrs["scene"] == SCENES[0].to_dict()

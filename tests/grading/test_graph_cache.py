"""The lab's live graph (Ex. 15's reference) is computed once and kept between grader runs, under a
name that changes with the reference pipeline's files."""

from __future__ import annotations

import json
import shutil

import pytest
from grading_helpers import REPO

from hri_teleop.grading.exercises.graph import check as checks
from hri_teleop.grading.exercises.graph.check import graph_cache_file, live_graph


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):


    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(checks, "_LIVE_GRAPH", {})
    return tmp_path / "cache"


def _copy_reference(dest):
    for folder in ("launch", "scripts", "config"):
        shutil.copytree(REPO / "hri_lab" / folder, dest / folder)
    return dest


@pytest.mark.ros
def test_the_live_graph_is_computed_once_and_read_back_by_the_next_run(fresh_cache, monkeypatch):


    graph = live_graph()
    cached = graph_cache_file()
    assert cached.parent.parent == fresh_cache and json.loads(cached.read_text()) == graph.to_json()
    assert "/teleoperation" in graph.publishers["/cartesian_velocity_controller/cmd_vel"]
    monkeypatch.setattr(checks, "_LIVE_GRAPH", {})

    def no_session(*_args, **_kwargs):
        raise AssertionError("the cached graph was computed again")

    monkeypatch.setattr(checks, "run_session_plan", no_session)
    assert live_graph() == graph


def test_the_cache_key_follows_the_reference_files_not_their_folder(tmp_path):
    from hri_teleop.grading.exercises.graph.check import graph_cache_file

    copy = _copy_reference(tmp_path / "copy")
    assert graph_cache_file(copy) == graph_cache_file(REPO / "hri_lab")
    launch = copy / "launch" / "teleoperation.launch"
    launch.write_text(launch.read_text() + "\n<!-- changed -->\n")
    assert graph_cache_file(copy) != graph_cache_file(REPO / "hri_lab")


def test_a_cut_short_cache_file_is_computed_again(fresh_cache, monkeypatch):

    from hri_teleop.grading.exercises.graph.session import LiveGraphObservation

    path = graph_cache_file()
    path.parent.mkdir(parents=True)
    path.write_text('{"kind": "live-gr')
    fake = LiveGraphObservation(problem="", publishers={}, subscribers={}, types={})
    monkeypatch.setattr(checks, "run_session_plan", lambda *_a, **_k: fake)
    assert live_graph() == fake
    assert json.loads(path.read_text()) == fake.to_json()

"""The bundle's container files say what the README promises (the build itself: make test-container)."""

from __future__ import annotations

import json
import re

import yaml

from hri_teleop.course.bundle import BUNDLE_FILES, BUNDLE_TOP, assemble_bundle

DOCKERFILE = (BUNDLE_FILES / "Dockerfile").read_text()


def test_the_base_is_a_build_argument_that_defaults_to_debian_12():
    lines = [line for line in DOCKERFILE.splitlines() if line and not line.startswith("#")]
    assert lines[0] == "ARG BASE=debian:12"
    assert lines[1] == "FROM ${BASE}"


def test_the_image_installs_with_the_bundles_own_make_setup_and_so_the_terms_pins():
    """make setup runs toolkit/tools/setup.sh, which installs with constraints.txt (tests/unit/test_pins.py)."""
    assert re.search(r"&& make setup\b", DOCKERFILE)
    assert "COPY toolkit ./toolkit" in DOCKERFILE
    assert re.search(r"^CMD \[\"make\", \"lab\",", DOCKERFILE, re.M)


def test_compose_keeps_the_students_folders_on_the_host_and_publishes_jupyterlab_and_the_3d_view_locally():
    compose = yaml.safe_load((BUNDLE_FILES / "compose.yaml").read_text())
    course = compose["services"]["course"]
    assert sorted(course["volumes"]) == ["./lab:/course/lab", "./preparation:/course/preparation"]
    assert course["ports"] == ["127.0.0.1:${HRI_LAB_PORT:-8888}:8888", "127.0.0.1:7000-7009:7000-7009"]
    assert course["build"]["args"]["BASE"] == "${BASE:-debian:12}"
    assert course["user"] == "${HRI_UID:-1000}:${HRI_GID:-1000}"


def test_the_devcontainer_opens_the_compose_service():
    config = json.loads((BUNDLE_FILES / ".devcontainer" / "devcontainer.json").read_text())
    assert config["dockerComposeFile"] == "../compose.yaml" and config["service"] == "course"
    assert 8888 in config["forwardPorts"] and 7000 in config["forwardPorts"]


def test_the_image_leaves_the_students_work_and_local_environments_out():
    ignored = (BUNDLE_FILES / ".dockerignore").read_text().split()
    assert {"preparation", "lab", "**/.venv"} <= set(ignored)


def test_the_bundle_carries_every_container_file_and_make_image(tmp_path):
    release = tmp_path / "release"
    (release / "preparation").mkdir(parents=True)
    bundle = assemble_bundle(release, tmp_path / "bundle", ["preparation"])
    for name in BUNDLE_TOP:
        assert (bundle / name).exists(), name
    assert (bundle / "toolkit" / "environment.yml").is_file()
    assert re.search(r"^image:", (bundle / "Makefile").read_text(), re.M)

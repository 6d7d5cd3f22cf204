"""A trial's sidecar: the YAML file beside its bag that says who did what, and what came after.

Metadata is written when a trial is recorded, the outcome and the questionnaire minutes later by
other commands, so every writer goes through :func:`update_sidecar`: it keeps the keys it does not
know and writes atomically. The keys: docs/experiment.md. Pure: YAML files only, no ROS.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import Any, Dict, Mapping, Union

import yaml

from hri_teleop.core.experiment.metrics import MetricsError, TrialMeta
from hri_teleop.core.files import replace_text
from hri_teleop.core.yamlfile import read_yaml

__all__ = ["META_KEYS", "read_sidecar", "write_sidecar", "update_sidecar", "meta_from_sidecar", "sidecar_data"]

#: The metadata keys, in the order they are written.
META_KEYS = ("participant", "object_name", "condition", "trial")


def read_sidecar(path: Union[str, Path]) -> Dict[str, Any]:
    """The sidecar's mapping; MetricsError naming the file for a missing, unreadable or malformed one."""
    data = read_yaml(path, MetricsError, what="trial sidecar",
                     missing_fix="give the .yaml written beside the trial's .bag (e.g. trials/P01_t01.yaml)")
    if not isinstance(data, dict):
        what = "it is empty" if data is None else f"the top level is a {type(data).__name__}, not a mapping"
        raise MetricsError(f"{path}: not a trial's sidecar ({what}); "
                           "restore it from the recording's /trial/metadata or record the trial again")
    return data


def meta_from_sidecar(data: Mapping[str, Any], path: Union[str, Path]) -> TrialMeta:
    """The trial's metadata from a sidecar's mapping; MetricsError naming ``path`` and the missing key."""
    try:
        return TrialMeta(str(data["participant"]), str(data["object_name"]), str(data["condition"]),
                         int(data["trial"]))
    except KeyError as exc:
        raise MetricsError(f"{path}: not a trial's metadata (no {exc.args[0]}); it needs "
                           f"{', '.join(META_KEYS)}") from None
    except (TypeError, ValueError) as exc:
        raise MetricsError(f"{path}: not a trial's metadata ({exc}); trial must be a number, "
                           "condition feedback or no_feedback") from None


def sidecar_data(meta: TrialMeta, extra: Mapping[str, Any]) -> Dict[str, Any]:
    """A new sidecar's content: the metadata first, then ``extra``."""
    data: Dict[str, Any] = dict(asdict(meta))
    data.update(extra)
    return data


def write_sidecar(path: Union[str, Path], data: Mapping[str, Any]) -> Path:
    """Write ``data`` as YAML to ``path`` atomically (temporary file in the same folder, then rename)."""
    path = Path(path)
    try:
        replace_text(path, yaml.safe_dump(dict(data), sort_keys=False))
    except OSError as exc:
        raise MetricsError(f"{path}: cannot write ({exc.strerror}); check that {path.parent} exists, is writable "
                           "and has free space") from None
    return path


def update_sidecar(path: Union[str, Path], updates: Mapping[str, Any]) -> Dict[str, Any]:
    """Set ``updates``' keys in an existing sidecar, keeping every other key; returns the new content.

    The file must already be a trial's sidecar (its metadata is checked first), so a typo
    in the path cannot create a stray file the analysis would then reject.
    """
    data = read_sidecar(path)
    meta_from_sidecar(data, path)
    data.update(updates)
    write_sidecar(path, data)
    return data

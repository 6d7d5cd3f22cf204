"""RehearsalOffer: the offer shows only while the folder holds no trial, and rehearsing fills it."""

from __future__ import annotations

from pathlib import Path

from hri_teleop.course.widgets.rehearsal import RehearsalOffer, count_trials


def _trial(folder: Path, stem: str, bag: bool = True) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{stem}.yaml").write_text("participant: P01\n")
    if bag:
        (folder / f"{stem}.bag").write_bytes(b"")


def test_a_trial_counts_only_with_its_bag_beside_its_sidecar(tmp_path):
    assert count_trials(tmp_path / "missing") == 0
    _trial(tmp_path, "P01_t01", bag=False)
    _trial(tmp_path, "plan", bag=False)
    assert count_trials(tmp_path) == 0
    _trial(tmp_path, "P01_t02")
    assert count_trials(tmp_path) == 1


def test_an_empty_folder_gets_the_offer_and_rehearsing_fills_it(tmp_path):
    calls = []

    def fake_rehearse(codes, objects, out, progress):
        calls.append((codes, objects, out))
        for code in codes:
            progress(f"{code} done")
            _trial(out, f"{code}_t01")
            _trial(out, f"{code}_t02")

    offer = RehearsalOffer(tmp_path / "trials", rehearse=fake_rehearse)
    assert "No recorded trials" in offer.status.value and offer.button.layout.display == ""
    offer.participants.value = 3
    assert offer.rehearse() == 6
    assert calls == [(["P01", "P02", "P03"], ["egg"], tmp_path / "trials")]
    assert offer.status.value.startswith("6 trial(s) in") and offer.button.layout.display == "none"
    assert not offer.button.disabled


def test_a_failed_rehearsal_is_one_line_and_keeps_the_offer(tmp_path, capsys):
    def broken(codes, objects, out, progress):
        raise RuntimeError("roscore on port 1 did not come up\nsecond line")

    offer = RehearsalOffer(tmp_path, rehearse=broken)
    assert offer.rehearse() == 0
    out = capsys.readouterr().out
    assert "rehearsal stopped: roscore on port 1 did not come up\n" in out and "second line" not in out
    assert offer.button.layout.display == "" and not offer.button.disabled


def test_trials_of_an_empty_folder_are_none_with_a_line_saying_how(tmp_path, capsys):
    offer = RehearsalOffer(tmp_path / "none", rehearse=lambda *a, **k: None)
    assert offer.trials() == []
    assert capsys.readouterr().out.startswith(f"no trials in {tmp_path / 'none'} yet: press Rehearse")

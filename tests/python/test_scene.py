"""The prostatesim module: arrays, commands and their errors, the GIL, snapshots, images,
metrics, saved states, and the state hash against `prostatesim replay --hash`."""
import json
import os
import subprocess
import threading

import numpy as np
import pytest

import prostatesim


def test_arrays_in_mm_and_the_scene_frame(biopsy):
    n = biopsy.particle_count
    x = biopsy.positions()
    x0 = biopsy.rest_positions()
    assert x.shape == (n, 3) and x.dtype == np.float64
    assert x0.shape == (n, 3)
    assert np.array_equal(x, x0)  # tick 0: at rest
    comp = biopsy.component_of()
    names = biopsy.component_names()
    assert comp.shape == (n,) and comp.min() == 0 and comp.max() == len(names) - 1
    prostate = x0[comp == names.index("prostate")]
    # the default gland: a few centimetres across, in millimetres
    extent = prostate.max(axis=0) - prostate.min(axis=0)
    assert np.all(extent > 20) and np.all(extent < 80), extent
    assert len(biopsy.tagged("lesion")) > 0
    roles = biopsy.component_roles()
    assert len(roles) == len(names) and roles[names.index("prostate")] == "prostate"
    assert roles[names.index("pubic_arch")] == "bone"
    assert biopsy.tag_roles()["lesion"] == "lesion" and biopsy.tag_roles()["peripheral"] == "other"
    with pytest.raises(ValueError, match="'tag'"):
        biopsy.tagged("no_such_tag")


def test_step_moves_time_and_releases_the_gil(biopsy):
    biopsy.step()
    assert biopsy.tick == 1 and biopsy.time == pytest.approx(biopsy.dt)
    # while one thread steps, another runs Python: the GIL is released during the step
    counter = 0
    t = threading.Thread(target=biopsy.step, args=(150,))
    t.start()
    while t.is_alive():
        counter += 1
    t.join()
    assert biopsy.tick == 151
    assert counter > 1000, counter
    with pytest.raises(ValueError):
        biopsy.step(-1)


@pytest.mark.parametrize("entry, key", [
    ({"probe": {"tilt_deg": "steep"}}, "probe.tilt_deg"),
    ({"probe": {"pitch_deg": 3}}, "probe.pitch_deg"),
    ({"advance": "biopsy_1"}, "speed_mm_s"),
    ({"poke": "biopsy_1"}, "command.poke"),
    ({"t": 1.0, "fire": "biopsy_1"}, "command.t"),
    ({"fire": "no_such_needle"}, "fire"),
    ({"fill_rate": "bladder", "ml_s": 1}, "fill_rate"),
])
def test_command_errors_name_the_key(biopsy, entry, key):
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):
        biopsy.command(entry)
    assert biopsy.tick == 0


def test_command_a_tool_refuses_is_a_value_error(biopsy):
    with pytest.raises(ValueError, match="refused"):
        biopsy.command({"probe": {"tilt_deg": 80}})
    assert biopsy.probe_pose()["tilt_deg"] == 0.0  # not taken


def test_probe_command_moves_the_probe(biopsy):
    before = next(t for t in biopsy.snapshot()["tools"] if t["kind"] == "probe")["tip_mm"]
    biopsy.command({"probe": {"insertion_mm": biopsy.probe_pose()["insertion_mm"] + 4}, "over_s": 0.1})
    biopsy.step(int(round(0.15 / biopsy.dt)))
    snap = biopsy.snapshot()
    probe = next(t for t in snap["tools"] if t["kind"] == "probe")
    moved = np.dot(np.subtract(probe["tip_mm"], before), probe["axis"])
    assert moved == pytest.approx(4.0, abs=0.05)
    assert snap["guide"] is not None and len(snap["guide"]["entry_mm"]) == 3


def test_ultrasound_planes(biopsy):
    for view in ("transverse", "sagittal"):
        img = biopsy.ultrasound(view)
        assert img.ndim == 2 and img.dtype == np.uint8
        assert img.shape[0] > 100 and img.shape[1] > 100
        assert img.std() > 5  # speckle and organs, not a blank frame
    with pytest.raises(ValueError, match="'view'"):
        biopsy.ultrasound("coronal")


def test_metrics_of_a_needle_session(biopsy):
    m = biopsy.metrics()
    assert "score" in m and "needles" in m
    json.dumps(m)


def write_script(path, entries, duration_s):
    # JSON is YAML: the script file is the same entries the Python commands send
    path.write_text(json.dumps({"scenario": "biopsy", "duration_s": duration_s, "timeline": entries}))


def test_state_hash_equals_replay_of_the_same_inputs(biopsy, biopsy_path, tmp_path):
    entries = [
        {"t": 0.0, "probe": {"insertion_mm": 45}, "over_s": 0.1},
        {"t": 0.1, "select": "biopsy_1"},
        {"t": 0.1, "advance": "biopsy_1", "speed_mm_s": 30},
        {"t": 0.24, "advance": "biopsy_1", "speed_mm_s": 0},
    ]
    duration = 0.3
    for e in entries:
        tick = int(round(e["t"] / biopsy.dt))
        biopsy.step(tick - biopsy.tick)
        biopsy.command({k: v for k, v in e.items() if k != "t"})
    biopsy.step(int(round(duration / biopsy.dt)) - biopsy.tick)
    script = tmp_path / "script.yaml"
    write_script(script, entries, duration)
    out = subprocess.run([os.environ["PROSTATESIM_BINARY"], "replay", biopsy_path, "--script", str(script), "--hash"],
                         capture_output=True, text=True, check=True, timeout=300)
    assert biopsy.state_hash() == out.stdout.strip()
    assert len(biopsy.state_hash()) == 16


def test_save_and_load_state_go_on_bit_for_bit(biopsy, tmp_path):
    biopsy.command({"probe": {"insertion_mm": 45}, "over_s": 0.05})
    biopsy.step(40)
    path = tmp_path / "s.state"
    biopsy.save_state(str(path))
    saved = biopsy.state_hash()
    biopsy.step(30)
    after = biopsy.state_hash()
    biopsy.load_state(str(path))
    assert biopsy.tick == 40 and biopsy.state_hash() == saved
    biopsy.step(30)
    assert biopsy.state_hash() == after
    path.write_text("not a state")
    with pytest.raises(ValueError):
        biopsy.load_state(str(path))


def test_bad_scenario_is_a_value_error(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\ntime: {dt_ms: -1}\n")
    with pytest.raises(ValueError, match="bad.yaml"):
        prostatesim.Scene(str(bad))

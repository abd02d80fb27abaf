"""render: the frame `plastivox render` draws, as an (h, w, 3) uint8 array."""

import numpy as np
import pytest

import plastivox
from conftest import run_cli

def test_render_matches_the_cli_png(tmp_path):
    robot = plastivox.demo_walker().with_physics({"duration": 0.3, "settle_time": 0.1})
    json_path = tmp_path / "walker.json"
    robot.save(json_path)
    ours = tmp_path / "py.png"
    img = plastivox.render(robot, time=0.15, size=(160, 120), out=ours)
    assert img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert img.std() > 5  # a robot, a floor and an overlay, not a blank frame
    cli = tmp_path / "cli.png"
    run_cli("render", str(json_path), "--out", str(cli), "--time", "0.15", "--size", "160x120")
    assert ours.read_bytes() == cli.read_bytes()
    # the same frame from the path, and from a Result of that robot
    assert np.array_equal(plastivox.render(str(json_path), time=0.15, size=(160, 120)), img)
    result = plastivox.simulate(robot)
    assert np.array_equal(plastivox.render(result, time=0.15, size=(160, 120)), img)
    stiff = plastivox.render(robot, time=0.15, size=(160, 120), color="stiffness", overlay=False)
    assert not np.array_equal(stiff, img)

def test_render_champion(tiny_run):
    path, _ = tiny_run
    res = plastivox.read_results(path)
    a = plastivox.render(res, time=0.2, size=(64, 48))
    b = plastivox.render(path, time=0.2, size=(64, 48))
    assert a.shape == (48, 64, 3) and np.array_equal(a, b)

def test_render_errors(tmp_path):
    robot = plastivox.demo_walker()
    with pytest.raises(ValueError, match="color"):
        plastivox.render(robot, color="plaid", size=(32, 32))
    with pytest.raises(ValueError, match="size"):
        plastivox.render(robot, size=(0, 32))
    with pytest.raises(TypeError, match="size"):
        plastivox.render(robot, size="big")
    with pytest.raises(ValueError, match="time"):
        plastivox.render(robot, time=99, size=(32, 32))
    with pytest.raises(TypeError, match="source"):
        plastivox.render(42)
    with pytest.raises(plastivox.InputError, match="absent.vxa"):
        plastivox.render(str(tmp_path / "absent.vxa"))
    with pytest.raises(plastivox.RenderError):
        plastivox.render(robot, size=(32, 32), out=str(tmp_path / "no" / "dir" / "x.png"))

def test_render_from_several_threads_gives_the_same_frames():
    """Two threads setting up the off-screen renderer at once failed an assertion in its UI
    backend and aborted the interpreter; calls from threads now take turns."""
    import threading
    robot = plastivox.demo_walker().with_physics({"duration": 0.3, "settle_time": 0.1})
    alone = plastivox.render(robot, time=0.15, size=(96, 72))
    frames, failures = [], []

    def work():
        try:
            frames.append(plastivox.render(robot, time=0.15, size=(96, 72)))
        except Exception as e:  # noqa: BLE001 - any failure is the test's finding
            failures.append(repr(e))

    workers = [threading.Thread(target=work) for _ in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert not failures
    assert len(frames) == 4 and all(np.array_equal(f, alone) for f in frames)


def test_colouring_by_actuation_shows_the_signal():
    robot = plastivox.demo_walker().with_physics({"duration": 0.6})
    by_actuation = plastivox.render(robot, time=0.5, color="actuation", size=(160, 120))
    by_stiffness = plastivox.render(robot, time=0.5, color="stiffness", size=(160, 120))
    assert by_actuation.shape == by_stiffness.shape == (120, 160, 3)
    assert np.mean(np.any(by_actuation != by_stiffness, axis=2)) > 0.02
    # Deterministic, and another time (another phase of the sine) gives other colours.
    assert np.array_equal(by_actuation,
                          plastivox.render(robot, time=0.5, color="actuation", size=(160, 120)))
    assert not np.array_equal(by_actuation,
                              plastivox.render(robot, time=0.55, color="actuation", size=(160, 120)))


def test_generation_applies_to_a_results_file_only(tiny_run, tmp_path):
    # A Robot, a Result, a robot file and a recorded life have one life: a generation given
    # with them is refused, not ignored.
    path, _ = tiny_run
    robot = plastivox.demo_walker().with_physics({"duration": 0.3, "settle_time": 0.1})
    json_path = tmp_path / "walker.json"
    robot.save(json_path)
    life = tmp_path / "life.h5"
    run_cli("simulate", str(json_path), "--record", str(life))
    for source in (robot, plastivox.simulate(robot), str(json_path), str(life)):
        with pytest.raises(ValueError, match=r"^generation: applies to a results file"):
            plastivox.render(source, generation=1, size=(32, 24))
    assert plastivox.render(robot, size=(32, 24)).shape == (24, 32, 3)
    assert plastivox.render(str(life), size=(32, 24)).shape == (24, 32, 3)
    res = plastivox.read_results(path)
    first = plastivox.render(res, generation=1, time=0.2, size=(32, 24))
    assert np.array_equal(first, plastivox.render(path, generation=1, time=0.2, size=(32, 24)))
    with pytest.raises(ValueError, match=r"^generation: expected a generation number or -1"):
        plastivox.render(res, generation=-2, size=(32, 24))

def test_the_lifes_own_end_time_renders():
    # A life ends at its first step past the duration: Result.sim_time is within it (the
    # last frame), a time well past it is not.
    robot = plastivox.demo_walker().with_physics({"duration": 0.3, "settle_time": 0.1})
    result = plastivox.simulate(robot)
    assert result.sim_time > 0.3
    last = plastivox.render(robot, time=result.sim_time, size=(64, 48))
    assert last.shape == (48, 64, 3) and last.std() > 5
    with pytest.raises(ValueError, match="time"):
        plastivox.render(robot, time=0.6, size=(64, 48))

def test_an_output_name_other_than_png_is_refused(tmp_path):
    robot = plastivox.demo_walker().with_physics({"duration": 0.3, "settle_time": 0.1})
    with pytest.raises(ValueError, match="PNG only"):
        plastivox.render(robot, time=0.1, size=(32, 24), out=tmp_path / "frame.jpg")
    assert not (tmp_path / "frame.jpg").exists()
    plastivox.render(robot, time=0.1, size=(32, 24), out=tmp_path / "frame.PNG")
    assert (tmp_path / "frame.PNG").exists()

def test_a_damaged_unsealed_life_is_an_error_not_a_crash(tmp_path):
    # Issue 54: a life without its seal, one byte changed, crashed (or hung) HDF5 inside the
    # interpreter. It is read in a separate process first (engine/io child_read.hpp).
    json_path = tmp_path / "small.json"  # a small body, as in the hostile run
    json_path.write_text('{"format": "plastivox-robot", "version": 1, "lattice": {"nx": 2, '
                         '"ny": 2, "nz": 1, "voxel_size": 0.01}, "voxels": [[0,0,0,1e9,0,0], '
                         '[1,0,0,1e9,0,0.5], [0,1,0,1e9,0,0], [1,1,0,1e9,0,0.5]]}')
    life = tmp_path / "life.h5"
    run_cli("simulate", str(json_path), "--preset", "gecco2018-code", "--duration", "0.3",
            "--record", str(life), "--fps", "10")
    unsealed = life.read_bytes()[512:]  # the 512-byte seal cut off
    plain = tmp_path / "plain.h5"
    plain.write_bytes(unsealed)
    assert np.array_equal(plastivox.render(str(plain), size=(32, 24)),
                          plastivox.render(str(life), size=(32, 24)))
    damaged = bytearray(unsealed)
    damaged[unsealed.index(b"GCOL") + 8] ^= 0xFF  # the global heap's size: HDF5 looped for ever
    bad = tmp_path / "bad.h5"
    bad.write_bytes(bytes(damaged))
    with pytest.raises(plastivox.InputError, match=r"bad\.h5: corrupt \(reading it in a separate "
                                                   r"process ended by signal"):
        plastivox.render(str(bad), size=(32, 24))

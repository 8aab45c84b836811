"""The Python package against the command line and the library's contracts: shapes, the
CLI's exact pixels, errors with their file:line: field, warnings, progressive rendering with a
callback, and KeyboardInterrupt stopping after a pass."""

import os
import _thread
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest

import gpu_photon as g

ROOT = Path(__file__).resolve().parents[2]
CORNELL = str(ROOT / "scenes" / "cornell-box.toml")


def cli():
    """The `gpu-photon` binary of this checkout (GPU_PHOTON_CLI, else the release build)."""
    if os.environ.get("GPU_PHOTON_CLI"):
        return os.environ["GPU_PHOTON_CLI"]
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = target / "release" / "gpu-photon"
    if path.exists():
        return str(path)
    if os.environ.get("CI") == "true":
        pytest.fail(f"no CLI at {path} (CI builds it before the Python tests)")
    pytest.skip(f"no CLI at {path}: run cargo build --release first")


def test_render_has_the_shape_and_type_asked_for():
    image = g.load(CORNELL).render(spp=4, passes=1, width=32, height=24, backend="cpu")
    assert image.shape == (24, 32, 3)
    assert image.dtype == np.float32 and image.flags["C_CONTIGUOUS"]
    assert np.isfinite(image).all()


def test_cornell_defaults_equal_the_cli_bit_for_bit(tmp_path):
    out = tmp_path / "cli.exr"
    size = ["--width", "32", "--height", "32"]
    cmd = [cli(), "render", CORNELL, "-o", str(out), "--backend", "cpu", "--quiet", *size]
    subprocess.run(cmd, check=True)
    ours = g.load(CORNELL).render(backend="cpu", width=32, height=32)
    theirs = g.read_image(out)
    assert ours.shape == theirs.shape == (32, 32, 3)
    assert np.array_equal(ours.view(np.uint32), theirs.view(np.uint32))
    # The mean of the Cornell box at these settings: white walls lit from above.
    assert 0.05 < ours.mean() < 1.0


def test_renderer_writes_the_clis_file_byte_for_byte(tmp_path):
    out = tmp_path / "cli.exr"
    size = ["--width", "32", "--height", "32", "--spp", "4"]
    cmd = [cli(), "render", CORNELL, "-o", str(out), "--backend", "cpu", "--quiet", *size]
    subprocess.run(cmd, check=True)
    r = g.Renderer(g.load(CORNELL), "cpu", width=32, height=32, spp=4)
    r.run()
    ours = tmp_path / "python.exr"
    r.write(ours)
    assert ours.read_bytes() == out.read_bytes()


def test_a_scene_error_names_file_line_and_field(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n[render]\ncaustic_radius = -1\n"
    )
    with pytest.raises(g.SceneError) as e:
        g.load(bad)
    assert str(e.value).startswith(f"{bad}:6: render.caustic_radius: must be positive")
    assert (e.value.file, e.value.line, e.value.field) == (str(bad), 6, "render.caustic_radius")


def test_settings_keep_the_cli_names_and_ranges():
    scene = g.load(CORNELL)
    with pytest.raises(g.SettingError, match=r"^invalid setting spp: 0 is outside 1\.\.=65536$"):
        scene.render(spp=0)
    with pytest.raises(g.SettingError, match="expected one of photon, direct"):
        scene.render(mode="fast")
    with pytest.raises(g.SettingError, match="unknown setting 'colour'"):
        scene.render(colour=1)
    with pytest.raises(OSError, match="missing.toml"):
        g.load(ROOT / "missing.toml")
    assert "caustic-photons" in g.setting_names
    assert scene.settings()["passes"] == 4


def test_warnings_go_through_the_warnings_module():
    with pytest.warns(g.GpuPhotonWarning, match="integrator `path` rendered with our photon mapping"):
        g.load(ROOT / "scenes" / "mitsuba" / "materials.xml")


def small_renderer(**settings):
    base = dict(width=16, height=16, spp=1, photons=2000, caustic_photons=200, backend="cpu")
    return g.Renderer(g.load(CORNELL), **{**base, **settings})


def test_progressive_rendering_calls_back_after_every_pass_and_can_stop():
    seen = []
    r = small_renderer(passes=6)
    r.run(lambda info: seen.append((info["pass"], info["done"], info["image"].shape)))
    assert seen == [(p, p + 1, (16, 16, 3)) for p in range(6)]
    assert r.done == (0, 6) and r.noise is not None

    stopper = small_renderer(passes=6)
    assert stopper.run(lambda info: info["done"] < 2) == 2
    assert stopper.done == (0, 2)
    assert stopper.run() == 4 and stopper.done == (0, 6)


def test_the_mean_of_passes_rendered_one_by_one_is_the_run():
    a, b = small_renderer(passes=3), small_renderer(passes=3)
    a.run()
    while b.render_pass():
        pass
    assert np.array_equal(a.image(), b.image())


def test_keyboard_interrupt_stops_after_the_pass():
    # What Ctrl-C does: SIGINT's flag is set while the render runs (here during pass 1's
    # callback); the exception comes out of run() before another pass starts.
    r = small_renderer(passes=1_000_000)

    def ctrl_c_after_second_pass(info):
        if info["done"] == 2:
            _thread.interrupt_main()

    # A shell's background job starts with SIGINT ignored; Python then raises nothing for it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            r.run(ctrl_c_after_second_pass)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert r.done == (0, 2)
    assert np.isfinite(r.image()).all() and r.image().mean() > 0


def test_diff_and_writers_match_the_cli(tmp_path):
    a = small_renderer(passes=2, seed=1)
    b = small_renderer(passes=2, seed=2)
    a.run()
    b.run()
    ia, ib = a.image(), b.image()
    pa, pb = tmp_path / "a.exr", tmp_path / "b.exr"
    g.write_exr(pa, ia)
    g.write_exr(pb, ib)
    assert np.array_equal(g.read_image(pa), ia)
    d = g.diff(ia, ib)
    printed = subprocess.run([cli(), "diff", str(pa), str(pb)], check=True, capture_output=True)
    assert printed.stdout.decode().splitlines() == d["lines"]
    assert d["rmse"] > 0 and g.diff(ia, ia)["rmse"] == 0
    g.write_png(tmp_path / "a.png", ia, exposure=1.0)
    assert g.read_image(tmp_path / "a.png").shape == (16, 16, 3)
    with pytest.raises(g.Error, match="expected a .exr file name"):
        g.write_exr(tmp_path / "a.png", ia)

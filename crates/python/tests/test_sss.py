"""The Python module `sss` against the libraries it binds and against exact identities. Run by
tests/python.rs (which builds the wheel), or by hand: pip install ./crates/python pytest, then
pytest crates/python/tests. SSS_BIN names the `sss` executable for the CLI comparisons."""

import ast
import json
import os
import signal
import subprocess
import sys
import threading
import time
import types
from pathlib import Path

import numpy as np
import pytest

import sss

ROOT = Path(__file__).resolve().parents[3]
SSS_BIN = os.environ.get("SSS_BIN")
QUICK = 100_000


@pytest.fixture(scope="module")
def skin1():
    return sss.simulate("skin1", photons=QUICK, seed=7)


def annulus_areas(p):
    """The area of each radial bin [cm²]: π(2i + 1)dr², MCML's annuli."""
    i = np.arange(len(p["r_cm"]))
    return np.pi * (2 * i + 1) * p["dr_cm"] ** 2


def test_rd_integrates_to_the_total(skin1):
    # Every photon leaving the top within the grid lands in one annulus, and the rest in MCML's
    # overflow bin: Σ Rd(r_i)·A_i over all bins is total Rd, to rounding.
    total = (skin1["rd"] * annulus_areas(skin1)[:, None]).sum(axis=0)
    np.testing.assert_allclose(total, skin1["rd_total"], rtol=1e-12)
    assert skin1["rd"].shape == (skin1["nr"], 3)
    assert np.all(skin1["rd_se"] >= 0)


def test_same_seed_same_numbers_for_any_thread_count(skin1):
    one = sss.simulate("skin1", photons=QUICK, seed=7, threads=1)
    for key in ("rd", "rd_se", "rd_total", "a_total", "tt_total"):
        assert np.array_equal(np.asarray(one[key]), np.asarray(skin1[key])), key


@pytest.mark.skipif(not SSS_BIN, reason="SSS_BIN not set")
def test_arrays_equal_the_cli_for_the_same_seed(skin1, tmp_path):
    subprocess.run([SSS_BIN, "simulate", "skin1", "--photons", str(QUICK), "--seed", "7",
                    "--out", str(tmp_path)], check=True, capture_output=True)
    csv = np.loadtxt(tmp_path / "skin1.profile.csv", delimiter=",", skiprows=1)
    # The CSV holds every bin (the overflow bin last) in Rust's shortest round-trip notation.
    assert np.array_equal(csv[:, 1:4], skin1["rd"])
    assert np.array_equal(csv[:, 4:7], skin1["rd_se"])
    summary = json.loads((tmp_path / "skin1.summary.json").read_text())
    for c, ch in enumerate("RGB"):
        assert summary["channels"][ch]["rd"] == skin1["rd_total"][c]


def test_a_dict_material_equals_the_same_builtin(skin1):
    m = next(m for m in sss.materials() if m["name"] == "skin1")
    coefficients = {k: m[k] for k in ("sigma_a", "sigma_s", "g", "eta")}
    d = sss.simulate(coefficients, photons=QUICK, seed=7)
    assert np.array_equal(d["rd"], skin1["rd"])


SKIN1 = {"sigma_a": [0.032, 0.17, 0.48], "sigma_s": [0.74, 0.88, 1.01], "g": 0.0, "eta": 1.3}


def layer(thickness=None, scale=10.0):
    """Skin1-like coefficients [cm⁻¹] × scale; a half-space without thickness."""
    d = {"sigma_a": [scale * x for x in SKIN1["sigma_a"]],
         "sigma_s": [scale * x for x in SKIN1["sigma_s"]], "g": 0.0, "eta": 1.3}
    if thickness is not None:
        d["thickness"] = thickness
    return d


def agree(a, b, key):
    """Two runs' totals agree within 4 combined standard errors per channel."""
    diff = np.abs(np.asarray(a[key]) - np.asarray(b[key]))
    se = np.hypot(a[key + "_se"], b[key + "_se"])
    assert np.all(diff <= 4 * se + 1e-12), (key, a[key], b[key], se)


def test_layers_trace_as_the_medium_they_stack():
    # A half-space cut into two layers of the same medium is the same half-space.
    one = sss.simulate({"layers": [layer()]}, photons=QUICK, seed=2)
    two = sss.simulate({"layers": [layer(0.05), layer()]}, photons=QUICK, seed=3)
    agree(one, two, "rd_total")
    assert two["a_layers"].shape == (3, 2)
    # ... and, traced layer by layer as MCML does, the same as the homogeneous material.
    homogeneous = sss.simulate(layer(), photons=QUICK, seed=4)
    agree(one, homogeneous, "rd_total")
    # A finite stack: every packet is reflected, absorbed or transmitted.
    stack = sss.simulate({"layers": [layer(0.02), layer(0.03, scale=3.0)]}, photons=QUICK,
                         seed=5, full=True)
    total = (np.asarray(stack["rsp"]) + stack["rd_total"] + stack["a_total"] + stack["tt_total"])
    np.testing.assert_allclose(total, 1.0, atol=1e-9)
    assert np.all(np.asarray(stack["tt_total"]) > 0)
    assert stack["a_rz"].shape == (3, stack["nr"], stack["nz"])
    np.testing.assert_allclose(stack["a_layers"].sum(axis=1), stack["a_total"], rtol=1e-9)


def test_simulate_releases_the_gil():
    # While one thread simulates, the main thread keeps running Python: holding the GIL would
    # stop it for the whole run. Ordered, not timed: once the worker is inside `simulate`, the
    # main thread runs a fixed loop of pure Python (tens of milliseconds) that must end while the
    # simulation (about a second of one thread) is still running. With the GIL held the loop
    # could not turn until the run returned, and would end after it.
    started, done = threading.Event(), threading.Event()

    def work():
        started.set()
        sss.simulate("marble", photons=400_000, seed=3, threads=1)
        done.set()

    def loop():
        turns = 0
        for _ in range(200_000):
            turns += 1
        return turns

    alone = time.perf_counter()
    loop()
    alone = time.perf_counter() - alone
    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    during = time.perf_counter()
    loop()
    during = time.perf_counter() - during
    finished_first = not done.is_set()
    worker.join()
    assert done.is_set()
    assert finished_first, "the main thread's loop ended only after the simulation: the GIL was held"
    print(f"the main thread's loop ran at {alone / during:.2f} of its own pace (measured, not asserted)")


def test_ctrl_c_interrupts_a_long_run():
    # A process started in the background by a non-interactive shell inherits SIGINT ignored, and
    # Python then installs no handler: the signal would be lost and the run never end. Ordered,
    # not timed: Ctrl-C half a second into a run of 10⁸ photons per channel (a minute or more on
    # two cores) must end it with KeyboardInterrupt; a lost signal lets it return normally.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sss.simulate("skin1", photons=10**8, seed=1)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    print(f"KeyboardInterrupt {time.perf_counter() - start - 0.5:.2f} s after Ctrl-C (measured, not asserted)")


def test_progress_reports_every_photon():
    seen = []
    sss.simulate("skin1", photons=QUICK, seed=1, progress=lambda done, total: seen.append((done, total)))
    # Every photon of every walk group (one per channel here) is counted once.
    assert seen and seen[-1][0] == seen[-1][1] and seen[-1][1] % QUICK == 0
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))


@pytest.mark.parametrize("material, kwargs, field", [
    ({"sigma_a": float("nan"), "sigma_s": 10.0, "eta": 1.3}, {}, "sigma_a"),
    ({"sigma_a": -1.0, "sigma_s": 10.0, "eta": 1.3}, {}, "sigma_a"),
    ({"sigma_a": [0.1, 0.2], "sigma_s": 10.0, "eta": 1.3}, {}, "sigma_a"),
    ({"sigma_a": "0.1", "sigma_s": 10.0, "eta": 1.3}, {}, "sigma_a"),
    ({"sigma_a": 0.1, "sigma_s": 10.0}, {}, "eta"),
    ({"sigma_a": 0.1, "sigma_s": 10.0, "eta": 1.3, "colour": 1}, {}, "material key"),
    ("skin1", {"photons": 10**15}, "photons"),
    ("skin1", {"photons": -5}, "photons"),
    ("skin1", {"photons": "many"}, "photons"),
    ("skin1", {"photons": 1.5}, "photons"),
    ("skin1", {"threads": 0}, "threads"),
    ({"layers": [layer(), layer()]}, {}, "layer 1 thickness"),
    ({"layers": []}, {}, "layers"),
    ({"layers": [dict(layer(), mu_a=1)]}, {}, "layer 1 key"),
    ({"layers": [layer(0.1)], "colour": 1}, {}, "layered material key"),
    ({"layers": [layer()]}, {"target_error": 0.01}, "target_error"),
    ("no-such-material", {}, "no-such-material"),
    (42, {}, "material"),
])
def test_hostile_input_raises_the_package_error(material, kwargs, field):
    with pytest.raises(sss.SssError, match=field):
        sss.simulate(material, **{"photons": 1000, **kwargs})
    assert issubclass(sss.SssError, ValueError)


def test_hostile_profiles_and_kernels_raise_the_package_error(skin1):
    bad = dict(skin1, rd=skin1["rd"][:, :2])
    with pytest.raises(sss.SssError, match="rd"):
        sss.fit(bad)
    with pytest.raises(sss.SssError, match="model"):
        sss.fit(skin1, model="svd99x")
    with pytest.raises(sss.SssError, match="taps"):
        sss.fit(skin1, taps=0)
    with pytest.raises(sss.SssError, match="format"):
        sss.export(sss.fit(skin1), format="cobol")
    with pytest.raises(sss.SssError):
        sss.read_mco("/dev/null")


def test_fit_then_export_round_trips_the_weights(skin1):
    for model in ("preint", "svd2-renorm"):
        k = sss.fit(skin1, model=model)
        out = json.loads(sss.export(k, format="json"))
        assert out["model"] == k.model == model
        for p, exported in enumerate(out["passes"]):
            # SSSS's layout: [r, g, b, offset], centre tap first; ours by increasing offset.
            got = np.array(sorted(exported["kernel"], key=lambda t: t[3]))
            np.testing.assert_allclose(got[:, 3], k.offsets[p], rtol=1e-6, atol=1e-9)
            np.testing.assert_allclose(got[:, :3], k.weights[p], rtol=1e-6, atol=1e-9)
            np.testing.assert_array_equal(exported["sign"], k.signs[p])
        # The kernel file reads back to the same kernel.
        again = sss.Kernel.from_toml(k.to_toml())
        np.testing.assert_allclose(again.weights, k.weights, rtol=1e-12)


def test_a_normalized_kernel_keeps_the_light(skin1):
    # Pre-integration's 1D weights sum to one per channel: a uniform image stays uniform.
    k = sss.fit(skin1, model="preint")
    np.testing.assert_allclose(k.weights[0].sum(axis=0), 1.0, rtol=1e-9)


def test_kernel_ranks_by_image_error(skin1):
    best, ranking = sss.kernel(skin1, budget="2x17")
    errors = [r["mean_image_rms"] for r in ranking]
    assert errors == sorted(errors)
    assert best.model == ranking[0]["model"]
    assert all(r["passes"] <= 2 for r in ranking)


@pytest.mark.skipif(not SSS_BIN, reason="SSS_BIN not set")
def test_evaluate_gives_the_rows_of_sss_eval(skin1, tmp_path):
    # The same profile (seed, photons) through `sss eval --json` and through Python: the same
    # models per channel with the same kernel- and image-space errors, bit for bit (the fit's
    # time aside).
    rows = sss.evaluate(skin1, material="skin1")
    cli = subprocess.run([SSS_BIN, "eval", "skin1", "--photons", str(QUICK), "--seed", "7",
                          "--profiles", str(tmp_path), "--json"],
                         check=True, capture_output=True, text=True)
    expected = json.loads(cli.stdout)["materials"][0]["models"]
    key = lambda r: (r["channel"], r["model"], r["kernel_rms"], r["l1_error"],
                     sorted(r["image_rms"].items()))
    assert {r["channel"] for r in rows} == {"R", "G", "B"} and len(expected) >= 9
    assert [key(r) for r in rows] == [key(r) for r in expected]


def test_analytic_profile_on_the_simulation_grid(skin1):
    p = sss.profile("skin1", model="pbd")
    assert p["rd"].shape == skin1["rd"].shape
    assert p["dr_cm"] == skin1["dr_cm"]
    assert np.all(p["rd"] >= 0)


@pytest.mark.skipif(not SSS_BIN, reason="SSS_BIN not set")
def test_engine_params_are_the_cli_fields(skin1, tmp_path):
    # The same profile (seed, photons) through `sss engine-params --json` and through Python:
    # every field's name, unit and value the same, bit for bit (JSON round-trips floats).
    e = sss.engine_params("skin1", engine="unreal", profile=skin1)
    cli = subprocess.run([SSS_BIN, "engine-params", "skin1", "--engine", "unreal", "--photons",
                          str(QUICK), "--seed", "7", "--profiles", str(tmp_path), "--json"],
                         check=True, capture_output=True, text=True)
    fields = json.loads(cli.stdout)["params"]["fields"]
    assert e["engine"] == "unreal" and len(fields) >= 3
    assert [(f["name"], f["unit"], f["value"]) for f in fields] == \
        [(f["name"], f["unit"], f["value"]) for f in e["params"]["fields"]]
    assert e["random_walk"] is None
    blender = sss.engine_params("skin1", engine="blender", profile=skin1)
    assert [f["name"] for f in blender["random_walk"]["fields"]][0] == "Base Color"
    # OpenPBR's parameters come from the coefficients themselves.
    assert sss.engine_params("skin1", engine="openpbr", profile=skin1)["params"]["fields"]


def test_a_material_is_simulated_where_a_profile_is_expected():
    # The same seed and photons: the same profile, so the same kernel and ranking.
    p = sss.simulate("skin1", photons=QUICK)
    direct, ranking = sss.kernel("skin1", photons=QUICK)
    via, ranking_via = sss.kernel(p, material=direct.material)
    assert direct.model == via.model and direct.material == "Skin1"
    assert np.array_equal(direct.weights, via.weights)
    assert ranking == ranking_via


MCI = ("1.0\n1\n# van de Hulst's slab\nslab.mco A\n20000\n0.01 0.01\n10 20 5\n1\n1.0\n"
       "1.0 10 90 0.75 0.02\n1.0\n")


def test_mcml_runs_conserve_energy_and_read_back(tmp_path):
    (tmp_path / "in.mci").write_text(MCI)
    runs = sss.run_mci(str(tmp_path / "in.mci"), seed=3)
    assert [r["out_name"] for r in runs] == ["slab.mco"] and runs[0]["photons"] == 20000
    r = runs[0]
    # Every packet is reflected (specularly or diffusely), absorbed or transmitted.
    assert abs(r["rsp"] + r["rd"] + r["a"] + r["tt"] - 1) < 1e-9
    assert r["a_rz"].shape == (20, 10)
    if SSS_BIN:
        # The same run written by `sss simulate --mci` and read back (MCML's 5 significant digits).
        subprocess.run([SSS_BIN, "simulate", "--mci", "in.mci", "--seed", "3", "--out", "res"],
                       cwd=tmp_path, check=True, capture_output=True)
        m = sss.read_mco(str(tmp_path / "res" / "slab.mco"))
        assert m["photons"] == 20000
        np.testing.assert_allclose([m["rd"], m["a"], m["tt"]], [r["rd"], r["a"], r["tt"]], rtol=1e-4)
        np.testing.assert_allclose(m["rd_r"], r["rd_r"], rtol=1e-4, atol=1e-12)


def test_every_name_has_a_stub():
    stub = ast.parse((Path(__file__).resolve().parents[1] / "sss.pyi").read_text())
    declared = {n.name for n in stub.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    # maturin wraps the extension in a package: its module object is not API.
    public = {n for n in dir(sss) if not n.startswith("_") and not isinstance(getattr(sss, n), types.ModuleType)}
    assert public <= declared, public - declared


def test_the_example_runs(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "kernels.py"),
                          "--out", str(tmp_path), "--photons", "100000"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "profiles_and_kernels.png").read_bytes()[:4] == b"\x89PNG"
    assert "float4" in (tmp_path / "skin1.hlsl").read_text()


def read_pfm(path):
    """A PFM file (bottom row first, little-endian) as height × width × 3, top row first."""
    kind, size, scale, pixels = Path(path).read_bytes().split(b"\n", 3)
    assert kind == b"PF" and float(scale) < 0
    width, height = map(int, size.split())
    return np.frombuffer(pixels, dtype="<f4").reshape(height, width, 3)[::-1]


@pytest.mark.skipif(not SSS_BIN, reason="SSS_BIN not set")
def test_render_equals_the_cli_pfm(tmp_path):
    # One request, two front ends: the same arguments give the same image, bit for bit.
    image = sss.render("skin1", scene="sphere", width=64, height=48, photons=QUICK)
    assert image.shape == (48, 64, 3) and image.dtype == np.float32
    subprocess.run([SSS_BIN, "render", "--material", "skin1", "--scene", "sphere", "--width", "64",
                    "--height", "48", "--photons", str(QUICK), "--profiles", str(tmp_path / "p"),
                    "--out", str(tmp_path / "r")], check=True, capture_output=True)
    cli = read_pfm(tmp_path / "r" / "render.pfm")
    assert np.array_equal(image, cli)
    # The plain kernel stays one argument away, and is another image.
    plain = sss.render("skin1", scene="sphere", width=64, height=48, photons=QUICK,
                       incidence_aware=False, exit_aware="off", entry_shift=False)
    assert not np.array_equal(plain, image)


def test_render_without_scattering_conserves_the_lambertian_light():
    # A flat floor-free view of the sphere lit head-on with no scattering is Lambert's law: the
    # brightest pixel, facing the light, is albedo × E / π (radiance); here linear radiance is
    # written ×π (as `sss render` writes irradiance-scaled radiance), so it is albedo × E.
    e, albedo = 2.0, 0.5
    image = sss.render("skin1", width=96, height=96, light=f"dir:0,0,1:{e}", camera=(0, 0, 20),
                       target=(0, 0, 0), object_albedo=albedo, floor_albedo=(0, 0, 0), specular=0,
                       ambient=0, no_sss=True)
    peak = image.reshape(-1, 3).max(axis=0)
    np.testing.assert_allclose(peak, albedo * e, rtol=0.02)


@pytest.mark.parametrize("kwargs, field", [
    ({"width": 0}, "width"),
    ({"method": "photon-mapping"}, "method"),
    ({"incidence_aware": "maybe"}, "incidence_aware"),
    ({"method": "directional-dipole", "entry_shift": True}, "entry_shift"),
    ({"method": "area-gather", "translucency": "on"}, "translucency"),
    ({"method": "surface-gather", "shape": True}, "shape"),
    ({"light": "sun:1,2,3"}, "light"),
    ({"scene": "pair"}, "material"),
    ({"exit_aware": "sideways"}, "exit_aware"),
    ({"photons": 0}, "photons"),
])
def test_render_refuses_bad_arguments_naming_them(kwargs, field):
    with pytest.raises(sss.SssError, match=field):
        sss.render("skin1", **{"width": 16, "height": 16, **kwargs})


def test_the_render_example_runs(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "render.py"),
                          "--out", str(tmp_path), "--photons", "100000", "--width", "96",
                          "--height", "54"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "render_comparison.png").read_bytes()[:4] == b"\x89PNG"
    assert np.load(tmp_path / "render_default.npy").shape == (54, 96, 3)


def test_render_prints_no_window_system_noise_on_a_headless_machine():
    # Without XDG_RUNTIME_DIR, Mesa's device-select layer would print "error: XDG_RUNTIME_DIR is
    # invalid or not set" twice though nothing failed; importing sss keeps it quiet.
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_RUNTIME_DIR", "NODEVICE_SELECT")}
    out = subprocess.run([sys.executable, "-c", "import sss; sss.render('skin1', width=16, height=16, "
                          "photons=20000, incidence_photons=2000)"], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert "XDG_RUNTIME_DIR" not in out.stderr and "error" not in out.stderr.lower(), out.stderr


def test_package_holds_the_tables_the_renderer_reads():
    # The package sss export writes, as bytes and arrays: ρ(0°)/ρ(0) is 1 by definition, the exit
    # law moves light between view angles and adds none (cosine-weighted mean 1 within 2 % for
    # the 10° steps), tables.bin is 718 vec4 whose first nine hold the incidence table, and the
    # shape table.
    p = sss.package("skin1", photons=QUICK, incidence_photons=20_000, translucency_photons=5_000)
    assert set(p["files"]) == {"README.md", "tables.json", "tables.bin", "kernel.json", "kernel.wgsl",
                               "kernel.glsl", "kernel.hlsl", "sss_lookups.wgsl", "sss_lookups.glsl",
                               "sss_lookups.hlsl"}
    np.testing.assert_array_equal(p["incidence"][0], [1.0, 1.0, 1.0])
    theta = np.radians(np.linspace(0.0, 90.0, 901)[:-1] + 0.05)
    t = np.minimum(np.degrees(theta) / 10.0, 8.0)
    for row in p["exit"]:
        h = np.stack([np.interp(t, np.arange(9), row[:, c]) for c in range(3)], axis=1)
        mean = (2 * np.cos(theta) * np.sin(theta) * np.radians(0.1))[:, None] * h
        np.testing.assert_allclose(mean.sum(axis=0), 1.0, atol=0.02)
    table = np.frombuffer(p["files"]["tables.bin"], dtype="<f4").reshape(718, 4)
    np.testing.assert_array_equal(table[:9, :3], p["incidence"])
    # It carries the shape table (on: shape_params.w = 1 after the 261 vec4 before it), whose E is
    # exactly 1 at κ = 0, the half-space against itself (node 7 of 15, 9 angles each).
    assert table[261, 3] == 1.0
    np.testing.assert_array_equal(table[266 + 9 * 7:266 + 9 * 8, :3], np.ones((9, 3)))
    tr = p["translucency"]
    assert tr["tt_over_rho"].shape == (16, 3) and np.all(np.diff(tr["tt_over_rho"], axis=0) <= 0)
    assert b"sss_exit" in p["files"]["sss_lookups.glsl"]
    with pytest.raises(sss.SssError, match="unobtainium"):
        sss.package("unobtainium")
    with pytest.raises(sss.SssError, match="incidence_photons"):
        sss.package("skin1", incidence_photons=-1)


def uv_sphere(radius, rings=48, segments=96):
    t = np.linspace(0, np.pi, rings + 1)
    p = np.linspace(0, 2 * np.pi, segments + 1)
    T, P = np.meshgrid(t, p, indexing="ij")
    n = np.stack([np.sin(T) * np.cos(P), np.cos(T), np.sin(T) * np.sin(P)], -1).reshape(-1, 3)
    row = segments + 1
    tri = [(i * row + j, i * row + j + 1, (i + 1) * row + j) for i in range(rings) for j in range(segments)]
    tri += [(i * row + j + 1, (i + 1) * row + j + 1, (i + 1) * row + j) for i in range(rings) for j in range(segments)]
    return radius * n, n, np.array(tri)


def test_light_scale_curvature_is_one_over_a_spheres_radius():
    # Every chord of a sphere has (n_y − n_x)·(y − x)/|y − x|² = 1/R: so has their average.
    for radius in (0.5, 3.0):
        p, n, tri = uv_sphere(radius)
        k = sss.light_scale_curvature(p, n, tri, [0.3, 0.1, 0.05])
        assert k.shape == (len(p), 3) and k.dtype == np.float32
        np.testing.assert_allclose(k, 1.0 / radius, rtol=2e-3)
    # Seen from inside (normals in), a cavity: −1/R.
    k = sss.light_scale_curvature(p, -n, tri, [0.3, 0.1, 0.05])
    np.testing.assert_allclose(k, -1.0 / 3.0, rtol=2e-3)


@pytest.mark.parametrize("args, field", [
    (dict(positions=np.zeros((3, 2))), "positions"),
    (dict(normals=np.zeros((2, 3))), "normals"),
    (dict(triangles=[[0, 1, 5]]), "triangles"),
    (dict(triangles=[[0, 1, 1.5]]), "triangles"),
    (dict(mean_cm=[0.1, 0.1]), "mean_cm"),
    (dict(mean_cm=[0.1, -0.1, 0.1]), "channel 1"),
])
def test_light_scale_curvature_refuses_bad_meshes_naming_them(args, field):
    base = dict(positions=np.eye(3), normals=[[0, 1, 0]] * 3, triangles=[[0, 1, 2]], mean_cm=[0.1, 0.1, 0.1])
    with pytest.raises(sss.SssError, match=field):
        sss.light_scale_curvature(**{**base, **args})

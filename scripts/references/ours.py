"""Our side of the comparisons: finding and running `sss`, the material files and profiles it
reads (`sss materials`, `sss simulate`), and every `sss render` one image comparison needs, read
back as linear radiance (`sss render` writes irradiance × albedo, π × radiance for a Lambertian
surface). Lengths are in centimetres, coefficients in 1/cm."""

import json
import math
import os
import subprocess
import sys
from dataclasses import dataclass

import numpy as np

from references.scenes import FRAME_LABELS, FRAME_SCALE, GATHER_LABELS
from references.scoring import blocks


def sss_binary(arg):
    """The `sss` executable: --sss, else target/release/sss, else the one on PATH."""
    if arg:
        return arg
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    local = os.path.join(root, "target", "release", "sss")
    return local if os.path.exists(local) else "sss"


def run(cmd, **kw):
    """Runs a command; on failure prints its stderr and exits."""
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.stderr.write(f"command failed: {' '.join(cmd)}\n{r.stderr}")
        sys.exit(2)
    return r.stdout


def material(sss, name):
    """A built-in material's coefficients [1/cm] per channel, from `sss materials --json`."""
    for m in json.loads(run([sss, "materials", "--json"]))["materials"]:
        if m["material"] == name:
            return m
    sys.exit(f"unknown material {name!r}")


def material_toml(m, eta, path, thickness=None):
    """Writes a material file of `material()`'s coefficients with the boundary η `eta` (and a slab
    `thickness` [cm], else a half-space) to `path`; returns the path."""
    ch = m["channels"]
    with open(path, "w") as f:
        f.write(f'name = "{m["material"]} (eta {eta})"\nunit = "cm"\n'
                f'sigma_a = [{", ".join(str(ch[c]["sigma_a_per_cm"]) for c in "RGB")}]\n'
                f'sigma_s = [{", ".join(str(ch[c]["sigma_s_per_cm"]) for c in "RGB")}]\n'
                f'g = [{", ".join(str(ch[c]["g"]) for c in "RGB")}]\neta = {eta}\n'
                + (f"thickness = {thickness}\n" if thickness else ""))
    return path


def read_profile(path):
    """(dr, rows) of a profile CSV written by `sss simulate`; rows are (r, [R,G,B], [seR,seG,seB]),
    the last (overflow) bin dropped. The bin width dr [cm] is the grid's, from the provenance file
    `sss simulate` writes beside the CSV (NAME.profile.json)."""
    lines = open(path).read().strip().split("\n")[1:]
    rows = []
    for line in lines:
        v = [float(x) for x in line.split(",")]
        rows.append((v[0], v[1:4], v[4:7]))
    provenance = json.load(open(path[: -len(".csv")] + ".json"))
    dr = provenance["channels"][0]["grid"]["dr"]
    return dr, rows[:-1]


def read_pfm(path):
    """An RGB PFM file (as `sss render` writes render.pfm) as float64 [height × width × 3], top row
    first."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return np.flipud(data).astype(np.float64)


@dataclass
class Medium:
    """The material as `sss` reads it in one comparison, all in a temporary folder."""
    toml: str              # material file of the scene's boundary η
    calibration_toml: str  # the same with η = 1, for the calibration's opaque surfaces
    rho: list              # total diffuse reflectance [R, G, B] of `toml`, the Lambertian albedo
    profile: str           # Rd(r) profile CSV `sss simulate` wrote for `toml`
    folder: str            # the folder of the profiles (`--profiles`)


def simulate_medium(sss, m, eta, photons, tmp):
    """Writes material `m` (as `material()` gives it) behind a boundary of index `eta` to `tmp`
    and simulates its profile with `photons` per channel: the Medium."""
    mat = material_toml(m, eta, os.path.join(tmp, "medium.toml"))
    # The calibration's opaque Lambertian surfaces have no dielectric boundary: η = 1 there.
    cal_mat = mat if eta == 1.0 else material_toml(m, 1.0, os.path.join(tmp, "calibration.toml"))
    run([sss, "simulate", mat, "--photons", str(photons), "--profile-only", "--out", tmp])
    summary = json.load(open(os.path.join(tmp, "medium.summary.json")))
    rho = [summary["channels"][c]["rd"] for c in "RGB"]
    profile = os.path.join(tmp, "medium.profile.csv")
    return Medium(mat, cal_mat, rho, profile, tmp)


def scene_view(setup, files):
    """A Setup's scene as `sss render` draws it, field by field (what `images.py --arrays` writes
    to view.json for `sss view --reference`): geometry (a generated mesh from `files`), image
    size, camera, black occluders, light and black floor, no specular or ambient light."""
    sc = setup.scene
    eye, target, fov = sc["camera"]
    kind, v, *rest = sc["light"]
    light = (f"area:{','.join(map(str, v))}:{','.join(map(str, rest[0]))}:{rest[1]}:{rest[2]}" if kind == "area"
             else f"{kind}:{v[0]},{v[1]},{v[2]}:{rest[0]}")
    return {"scene": files.get("bust", sc.get("geometry", setup.name)), "width": setup.width,
            "height": setup.height, "camera": list(eye), "target": list(target), "fov_deg": fov,
            "boxes": [":".join(",".join(map(str, c)) for c in box) for box in sc["boxes"]],
            "lights": [light], "floor_albedo": [0.0, 0.0, 0.0], "specular": 0.0, "ambient": 0.0}


def scene_args(setup, files):
    """`sss render`'s arguments for a Setup's scene (`scene_view`)."""
    v = scene_view(setup, files)
    return ["--scene", v["scene"], "--width", str(v["width"]), "--height", str(v["height"]),
            "--camera=" + ",".join(map(str, v["camera"])), "--target=" + ",".join(map(str, v["target"])),
            "--fov", str(v["fov_deg"]), *["--box=" + b for b in v["boxes"]],
            *["--light=" + x for x in v["lights"]], "--floor-albedo", "0,0,0",
            "--specular", "0", "--ambient", "0", "--albedo", "pre-post"]


def render(sss, args, out):
    """`sss render ARGS --out OUT`, read back as linear radiance [height × width × 3]."""
    run([sss, "render", *args, "--out", out])
    return read_pfm(os.path.join(out, "render.pfm")) / math.pi


@dataclass
class Renders:
    """Our renders of one comparison, each linear radiance [height × width × 3]."""
    wrong: np.ndarray      # the negative control: --no-sss with the albedo × 0.8
    lambertian: np.ndarray  # the calibration: --no-sss on the same surfaces
    images: dict           # each model's image, by label
    gather_noise: dict     # the surface gathers' two half renders' difference on 2×2 blocks, by label


def render_ours(sss, setup, files, medium, tmp):
    """Every `sss render` of one comparison: the negative control, the calibration and each of
    the Setup's models (rendered into `tmp`)."""
    common = scene_args(setup, files)
    rho, cal_mat = medium.rho, medium.calibration_toml
    albedo = ["--object-albedo", ",".join(f"{r:.6f}" for r in rho)]
    # The negative control: a deliberately wrong render (albedo × 0.8) the calibration must
    # reject, so the instrument is shown to be able to fail.
    wrong = render(sss, [*common, "--object-albedo", ",".join(f"{0.8 * r:.6f}" for r in rho),
                         "--no-sss", "--material", cal_mat], os.path.join(tmp, "wrong"))
    # The calibration render: `--no-sss` on the same surfaces (the `lambert` model's image
    # where the boundary is index-matched; behind a dielectric one, `lambert` also mirrors the
    # area light, which Mitsuba's opaque Lambertian surfaces do not).
    lambertian = render(sss, [*common, *albedo, "--no-sss", "--material", cal_mat], os.path.join(tmp, "calibration"))
    images, gather_noise = {}, {}
    for label, fit_args, extra in setup.scene["models"]:
        rdir = os.path.join(tmp, label)
        extra = [x.replace("{material}", medium.toml).replace("{profiles}", medium.folder)
                 .replace("{frames}", str(setup.gather_frames)).replace("{table_photons}", str(setup.table_photons))
                 for x in extra]
        if label in FRAME_LABELS:
            images[label] = render_frame(sss, setup, files, [*albedo, *extra], rdir)
        elif label in GATHER_LABELS:
            halves = [render(sss, [*common, *albedo, *extra, "--frame-seed", str(seed)], rdir) for seed in (1, 2)]
            images[label] = 0.5 * (halves[0] + halves[1])
            gather_noise[label] = blocks(halves[0]) - blocks(halves[1])
        else:
            images[label] = render_model(sss, setup, medium, [*common, *albedo], label, fit_args, extra, rdir, tmp)
    return Renders(wrong, lambertian, images, gather_noise)


def render_frame(sss, setup, files, args, out):
    """A one-frame method as users see it: rendered at FRAME_SCALE times the Setup's size and
    averaged onto its pixels (each the mean of the FRAME_SCALE² pixels it covers)."""
    k = FRAME_SCALE
    big = scene_args(setup, files)
    big[big.index("--width") + 1], big[big.index("--height") + 1] = str(k * setup.width), str(k * setup.height)
    image = render(sss, [*big, *args], out)
    return image.reshape(setup.height, k, setup.width, k, 3).mean(axis=(1, 3))


def explicit_off(args, flags):
    """`FLAG off` for each of `flags` that `args` does not give."""
    return [x for flag in flags if flag not in args for x in (flag, "off")]


def render_model(sss, setup, medium, args, label, fit_args, extra, rdir, tmp):
    """One model's `sss render` (its MODELS entry: `label`, `fit_args` for `sss fit`, None for
    no scattering, and `extra` render arguments) into `rdir`, with the kernel fitted into
    `tmp`: its image."""
    # The material names the boundary's η (the mirror image of an area light) to every model.
    if "--material" not in extra:
        extra = [*extra, "--material", medium.toml]
    # `sss render` shades with the incidence, exit and entry-shift tables by default; each model
    # uses the ones it names.
    extra = [*extra, *explicit_off(extra, ["--incidence-aware", "--exit-aware", "--entry-shift"])]
    if fit_args is None:
        return render(sss, [*args, *extra, "--no-sss"], rdir)
    if not fit_args:
        return render(sss, [*args, *extra], rdir)
    # `sss render` lets light through thin parts by default; the models compare with it only
    # where they say so.
    extra = [*extra, *explicit_off(extra, ["--translucency"])]
    kernel = os.path.join(tmp, f"{label}.toml")
    run([sss, "fit", medium.profile, *fit_args, "--taps", "33", "--material", setup.material, "--out", kernel])
    return render(sss, [*args, *extra, "--kernel", kernel], rdir)

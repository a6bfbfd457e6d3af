"""The scenes `sss render` is compared against Mitsuba 3 on: cameras, lights, geometry (and the
generated bust mesh), the models each scene compares, and the size and sample budget a run
renders them at. Lengths are in centimetres, angles in degrees."""

import math
import sys
from dataclasses import dataclass

import numpy as np

# gpu::Scene::sphere()'s camera, zoomed onto the sphere's lit face, across which a black bar
# between the light and the sphere casts a hard shadow: the edges scattering softens.
CAMERA = ((0.0, 9.0, 24.0), (-1.5, 6.5, 3.0), 16.0)
BAR = ((-5.2, 10.4, -2.0), (-4.2, 11.4, 12.0))        # black occluder [cm]
LIGHT = (-12.0, 20.0, 14.0)                           # point light [cm]
INTENSITY = 500.0                                     # irradiance × cm²
# Maisch & Ropinski 2020 for long mean free paths: the area pre-integrated profile gathered over
# their layered pattern, plus splats where the camera does not see; and the brute-force 2D
# screen-space gather of the same kernel (every pixel within 48 px) with the same splats.
AREA = [
    ("area-gather", [], ["--method", "area-gather", "--material", "{material}", "--profiles", "{profiles}"]),
    ("area-gather-dense", [], ["--method", "area-gather", "--material", "{material}", "--profiles", "{profiles}",
                               "--gather-inner", "48", "--gather-layers", "0"]),
    # ... with the angular dependence of total reflectance and of the exit direction, as for preint.
    ("area-gather-incidence-exit", [], ["--method", "area-gather", "--material", "{material}",
                                        "--profiles", "{profiles}", "--incidence-aware", "on", "--exit-aware", "on"]),
]
# The material's own Monte Carlo BSSRDF gathered over the lit surface (`--method surface-gather`;
# an area light is drawn as four new points on it per frame): the error budget's references on
# our side. Radial: the
# profile at the 3-D distance with the incidence and exit tables, the best any radial-profile
# method can reach with exact geometry and visibility; directional: mc's Rd(x, y; θ) at oblique
# incidence. Each is rendered twice with independent frame seeds ({frames} frames each): their
# mean is the image, their difference its noise, corrected for as the reference's is.
GATHER_ARGS = ["--method", "surface-gather", "--material", "{material}", "--profiles", "{profiles}",
               "--samples", "32", "--frames", "{frames}", "--light-map", "2048",
               "--incidence-photons", "{table_photons}"]
# Shape-aware (issue 47): the directional gather scaled by mc's transport in spheres and cavities
# of each chord's curvature (E(κ, θ) and the spread's stretch), the error budget's "shape" term.
GATHERS = [("surface-gather-radial", [], [*GATHER_ARGS, "--bssrdf", "radial"]),
           ("surface-gather-directional", [], [*GATHER_ARGS, "--bssrdf", "directional"]),
           ("surface-gather-shape", [], [*GATHER_ARGS, "--bssrdf", "shape"])]
GATHER_LABELS = [g[0] for g in GATHERS]
# The shape-aware gather in one frame (issue 60): N samples per pixel and light, one frame, with
# and without the edge-aware denoiser (`--denoise`), rendered as users see it, FRAME_SCALE times
# the reference's size (1920×1080 at CI size), and averaged onto the reference's pixels (each
# reference pixel the mean of the FRAME_SCALE² pixels it covers). Its own noise counts as error:
# it is rendered once, and only the reference's noise is removed.
FRAME_SCALE = 10
FRAME_SAMPLES = (1, 2, 4, 8, 16)
FRAME_ARGS = ["--method", "surface-gather", "--bssrdf", "shape", "--material", "{material}",
              "--profiles", "{profiles}", "--frames", "1", "--light-map", "2048",
              "--incidence-photons", "{table_photons}"]
FRAMES = [(f"gather-frame-{n}spp{'-denoised' if d else ''}", [],
           [*FRAME_ARGS, "--samples", str(n), "--denoise", "on" if d else "off"])
          for n in FRAME_SAMPLES for d in (False, True)]
FRAME_LABELS = [f[0] for f in FRAMES]
# CI's quick run keeps the one-frame gather at 4 samples (with and without the denoiser), about a
# minute on 2 cores for the three scenes; the full run scores every count.
QUICK_FRAME_SAMPLES = (4,)
MODELS = [  # label, `sss fit` arguments (None: no scattering), extra `sss render` arguments
    ("lambert", None, []),
    ("preint", ["--model", "preint"], []),
    # The depth tests compared (the default above is the thesis's lerp, eq. 4.12).
    ("preint-reject", ["--model", "preint"], ["--depth-test", "reject"]),
    ("preint-nodepth", ["--model", "preint"], ["--depth-test", "none"]),
    # The SSSS supplement's depth factor e^{−Δz²/2τmax} (§E), not renormalized.
    ("preint-gaussian", ["--model", "preint"], ["--depth-test", "gaussian"]),
    ("svd1", ["--model", "svd", "--rank", "1", "--renormalize"], []),
    ("svd3", ["--model", "svd", "--rank", "3", "--renormalize"], []),
    ("deon3", ["--model", "deon", "--rank", "3"], []),
    ("guided", ["--model", "guided"], []),
    ("burley", ["--model", "burley"], []),
    # Incidence-aware shading (ρ(θ)/ρ(0) from `mc` for the η = 1 material, issue 15 item 4).
    ("preint-incidence", ["--model", "preint"], ["--incidence-aware", "on", "--material", "{material}"]),
    # ... and exit-angle-aware (h(θ_o): the reflected radiance over a Lambertian surface's, from
    # `mc`, of light that entered along the normal) ...
    ("preint-incidence-exit", ["--model", "preint"],
     ["--incidence-aware", "on", "--exit-aware", "on", "--material", "{material}"]),
    # ... or read at the entry angle of each pixel's lights (h(θ_o; θ_i)).
    ("preint-incidence-exit-entry", ["--model", "preint"],
     ["--incidence-aware", "on", "--exit-aware", "entry", "--material", "{material}"]),
    # ... with each light's entry moved δ(θ) back along its propagation over the surface: light
    # entering a half-space at θ leaves centred δ ahead of its entry (`--entry-shift`, issue 30).
    ("preint-incidence-exit-entry-shift", ["--model", "preint"],
     ["--incidence-aware", "on", "--exit-aware", "entry", "--entry-shift", "on", "--material", "{material}"]),
    # ... and the body's shape: each light's entering light times E(κ, θ), what a sphere or a
    # cavity of the surface's mean curvature returns over a half-space (`--shape`, issue 47).
    ("preint-incidence-exit-entry-shift-shape", ["--model", "preint"],
     ["--incidence-aware", "on", "--exit-aware", "entry", "--entry-shift", "on", "--shape", "on",
      "--material", "{material}"]),
    # No kernel: the directional dipole integrated per pixel over lit points (`--method`), as
    # published and rescaled to the Monte Carlo total reflectance.
    ("directional-dipole", [], ["--method", "directional-dipole", "--material", "{material}",
                                "--dipole-energy", "published",
                                "--samples", "32", "--frames", "32", "--light-map", "2048"]),
    ("directional-dipole-mc", [], ["--method", "directional-dipole", "--material", "{material}",
                                   "--profiles", "{profiles}",
                                   "--samples", "32", "--frames", "32", "--light-map", "2048"]),
    *AREA,
    *GATHERS,
    *FRAMES,
]

# Thin parts: gpu::Scene::fin()'s sphere and its 3 mm and 1 mm fins, seen from the default camera
# side, lit by a directional light from behind the fins (−x), so the faces the camera sees get
# light only through the fins (and around the sphere's silhouette).
FIN_MODELS = [
    ("lambert", None, []),
    ("preint", ["--model", "preint"], []),
    ("preint-translucency", ["--model", "preint"],
     ["--translucency", "on", "--material", "{material}", "--profiles", "{profiles}"]),
    # Much of the visible sphere is lit at grazing incidence here: both corrections together.
    ("preint-incidence-translucency", ["--model", "preint"],
     ["--translucency", "on", "--incidence-aware", "on", "--material", "{material}",
      "--profiles", "{profiles}"]),
    ("preint-incidence-translucency-exit", ["--model", "preint"],
     ["--translucency", "on", "--incidence-aware", "on", "--exit-aware", "on", "--material", "{material}",
      "--profiles", "{profiles}"]),
    ("preint-incidence-translucency-exit-entry", ["--model", "preint"],
     ["--translucency", "on", "--incidence-aware", "on", "--exit-aware", "entry", "--material", "{material}",
      "--profiles", "{profiles}"]),
    ("preint-incidence-translucency-exit-entry-shift", ["--model", "preint"],
     ["--translucency", "on", "--incidence-aware", "on", "--exit-aware", "entry", "--entry-shift", "on",
      "--material", "{material}", "--profiles", "{profiles}"]),
    ("preint-incidence-translucency-exit-entry-shift-shape", ["--model", "preint"],
     ["--translucency", "on", "--incidence-aware", "on", "--exit-aware", "entry", "--entry-shift", "on",
      "--shape", "on", "--material", "{material}", "--profiles", "{profiles}"]),
    ("directional-dipole-mc", [], ["--method", "directional-dipole", "--material", "{material}",
                                   "--profiles", "{profiles}",
                                   "--samples", "32", "--frames", "32", "--light-map", "2048"]),
    *AREA,
    *GATHERS,
    *FRAMES,
]

# Small features and depth discontinuities: the depth tests, the incidence-aware shading.
BUST_MODELS = [m for m in MODELS if m[0] in (
    "lambert", "preint", "preint-reject", "preint-nodepth", "preint-gaussian", "svd1", "svd3",
    "preint-incidence",
    "preint-incidence-exit", "preint-incidence-exit-entry", "preint-incidence-exit-entry-shift",
    "preint-incidence-exit-entry-shift-shape", "area-gather", *GATHER_LABELS, *FRAME_LABELS)]

# A smooth dielectric boundary (η = 1.3) lit by a square area light: what the index-matched scenes
# leave out. Light enters through Fresnel transmission and leaves by refraction, so Mitsuba cannot
# connect to the light from inside the medium: paths must hit it, and a large light keeps the
# noise down. The sphere mirrors the light in its boundary; `sss render` adds that reflection
# (F(η, θ) × L where the mirror ray meets the light) on SSS surfaces. The same bar casts a soft
# shadow.
AREA_LIGHT = ((-12.0, 20.0, 14.0), (0.0, 5.0, 0.0), 12.0, 6.0)   # centre, aim [cm], side [cm], radiance
DIELECTRIC_MODELS = [m for m in MODELS if m[0] in (
    "lambert", "preint", "svd1", "svd3", "preint-incidence", "preint-incidence-exit", "preint-incidence-exit-entry",
    "preint-incidence-exit-entry-shift", *GATHER_LABELS)]

# The bust and the fins behind the same boundary under a small light (issue 30): a 3 cm square
# whose penumbrae (a few mm where the nose, the brow and the fins cast shadows) are no wider than
# Skin1's scattering, so the kernels' shapes show, unlike under the dielectric sphere's 12 cm
# light, with the irradiance of the index-matched scene's light at the subject (L·s²/d²). Paths
# must hit the small light by chance: the samples per pixel grow with the solid angle it no
# longer has. The fins' light sits where the fin scene's sun is seen from them, 16 cm away. The
# bust's sits 14 cm from its centre in front of and above the face (a key light: the nose and
# brow shade the lip and the eyes' hollows), not where the bust scene's point light is: from
# there the camera sees mostly the side turned away from the light, whose light must cross the
# head before it finds the light by chance (reference noise 60 % per 2×2 block at 1,024 spp
# against about 25 % from the front, so 6× the samples for the same noise).
BUST_AREA_LIGHT = ((2.8, 13.4, 10.8), (0.0, 5.0, 0.0), 3.0, 20.0)
FIN_AREA_LIGHT = ((-10.5, 9.9, 6.7), (3.0, 4.5, 0.0), 3.0, 57.0)
DIELECTRIC_FIN_MODELS = [m for m in FIN_MODELS if m[0] in (
    "lambert", "preint", "preint-incidence", "preint-incidence-exit", "preint-incidence-translucency",
    "preint-incidence-translucency-exit", "preint-incidence-translucency-exit-entry",
    "preint-incidence-translucency-exit-entry-shift", *GATHER_LABELS)]
# The area gather splats light from surface the camera does not see, which the bust's visible
# side (facing away from the light) lacks most.
DIELECTRIC_BUST_MODELS = [m for m in MODELS if m[0] in (
    "lambert", "preint", "svd1", "svd3", "preint-incidence", "preint-incidence-exit", "preint-incidence-exit-entry",
    "preint-incidence-exit-entry-shift", "area-gather",
    "area-gather-incidence-exit", *GATHER_LABELS)]

# camera (eye, target, vertical fov [deg]); SSS media (sphere: centre, radius; box: corners [cm],
# the geometry of `gpu::Scene`; obj: a generated mesh); black occluders; light (point: position, intensity; dir: towards
# the light, irradiance; area: centre, aim, side, radiance); the boundary's η (1: index-matched);
# `sss render`'s --scene where it is not the scene's name; the models compared; whether the kernel
# shapes' order is checked (default) or reported; a factor on the samples per pixel.
SCENES = {
    "sphere": {"camera": CAMERA, "media": [("sphere", (0.0, 5.0, 0.0), 5.0)], "boxes": [BAR],
               "light": ("point", LIGHT, INTENSITY), "models": MODELS},
    "fin": {"camera": ((4.0, 8.0, 22.0), (2.5, 4.5, 0.0), 24.0),
            "media": [("sphere", (-4.0, 4.0, 0.0), 4.0), ("box", (1.5, 0.0, -3.0), (1.8, 9.0, 3.0)),
                      ("box", (4.5, 0.0, -2.0), (4.6, 6.0, 2.0))],
            "boxes": [], "light": ("dir", (-1.0, 0.4, 0.5), 2.0), "models": FIN_MODELS},
    # bust_obj()'s mesh seen from the side, so its nose hides part of the cheek.
    "bust": {"camera": ((16.0, 8.0, 18.0), (0.0, 5.0, 0.0), 28.0), "media": [("obj", "bust")], "boxes": [],
             "light": ("point", LIGHT, INTENSITY), "models": BUST_MODELS},
    "dielectric": {"camera": CAMERA, "media": [("sphere", (0.0, 5.0, 0.0), 5.0)], "boxes": [BAR],
                   "light": ("area", *AREA_LIGHT), "eta": 1.3, "geometry": "sphere", "models": DIELECTRIC_MODELS,
                   # The large light's irradiance is smooth: the kernels differ from each other and
                   # from Lambertian shading (which mirrors the light too) by a few tenths of a
                   # point here, and their order is reported, not required.
                   "kernel_order": False, "spp_factor": 3},
    "bust-dielectric": {"camera": ((16.0, 8.0, 18.0), (0.0, 5.0, 0.0), 28.0), "media": [("obj", "bust")],
                        "boxes": [], "light": ("area", *BUST_AREA_LIGHT), "eta": 1.3,
                        "models": DIELECTRIC_BUST_MODELS, "spp_factor": 16},
    "fin-dielectric": {"camera": ((4.0, 8.0, 22.0), (2.5, 4.5, 0.0), 24.0),
                       "media": [("sphere", (-4.0, 4.0, 0.0), 4.0), ("box", (1.5, 0.0, -3.0), (1.8, 9.0, 3.0)),
                                 ("box", (4.5, 0.0, -2.0), (4.6, 6.0, 2.0))],
                       "boxes": [], "light": ("area", *FIN_AREA_LIGHT), "eta": 1.3, "geometry": "fin",
                       "models": DIELECTRIC_FIN_MODELS, "spp_factor": 8},
}


def folder(scene, material):
    """The output folder's name of one scene and material: images[-SCENE][-MATERIAL], the
    sphere and Skin1 left unnamed."""
    return ("images" if scene == "sphere" else f"images-{scene}") + ("" if material == "skin1" else f"-{material}")


@dataclass
class Setup:
    """One comparison as it is rendered: the scene, its models, the image size and the sample
    budgets of both renderers."""
    name: str            # the scene's key in SCENES
    material: str        # the built-in material's name
    scene: dict          # its SCENES entry, the models narrowed to those asked for
    width: int           # image width [px]
    height: int          # image height [px]
    spp: int             # Mitsuba's samples per pixel for the reference (its two halves together)
    cal_spp: int         # Mitsuba's samples per pixel for the calibration (its two halves together)
    photons: int         # `sss simulate` photons per channel for the profiles the kernels fit
    gather_frames: int   # the surface gathers' frames per seed (two seeds)
    table_photons: int   # photons per channel and angle of the surface gathers' tables


def setup(name, material, quick, models=None):
    """The Setup of scene `name` with `material`: CI size with `quick`, else full size; `models`
    (comma-separated labels, or None for all) narrows the scene's models (lambert is always
    kept). Exits if a label is not among the scene's models."""
    width, height, spp, photons = (192, 108, 128, 300_000) if quick else (384, 216, 1024, 10_000_000)
    # The surface gathers: frames per seed (two seeds), and photons per channel and angle of their
    # angle and directional tables.
    gather_frames, table_photons = (8, 100_000) if quick else (64, 1_000_000)
    # Paths that must find the light by chance (behind a dielectric boundary) need more samples.
    spp *= SCENES[name].get("spp_factor", 1)
    # Opaque surfaces lit directly by a point or directional light converge fast: a quarter of
    # the samples. Direct light from an area light is sampled over its surface: all of them.
    cal_spp = spp if SCENES[name]["light"][0] == "area" else max(spp // 4, 16)
    sc = dict(SCENES[name])
    if quick and not models:
        sc["models"] = [m for m in sc["models"] if m[0] not in FRAME_LABELS
                        or any(m[0].startswith(f"gather-frame-{n}spp") for n in QUICK_FRAME_SAMPLES)]
    if models:
        keep = set(models.split(",")) | {"lambert"}
        unknown = keep - {m[0] for m in sc["models"]}
        if unknown:
            sys.exit(f"--models: {', '.join(sorted(unknown))} not among the {name} scene's models")
        sc["models"] = [m for m in sc["models"] if m[0] in keep]
    return Setup(name, material, sc, width, height, spp, cal_spp, photons, gather_frames, table_photons)


def bust_obj(path):
    """A closed, star-shaped "bust" (a head-sized blob with a nose, ears and a brow ridge: small
    features that occlude the surface behind them, so the camera sees depth discontinuities), as
    OBJ text with area-weighted vertex normals, already in `gpu::Scene::obj`'s frame (10 cm tall,
    centred on x and z, standing on y = 0), so both renderers read the same surface."""
    nt, nph = 120, 240
    t = np.linspace(0, math.pi, nt + 1)[1:-1]
    ph = np.linspace(0, 2 * math.pi, nph, endpoint=False)
    T, P = np.meshgrid(t, ph, indexing="ij")
    d = np.stack([np.sin(T) * np.sin(P), np.cos(T), np.sin(T) * np.cos(P)], -1).reshape(-1, 3)
    d = np.concatenate([[[0, 1, 0]], d, [[0, -1, 0]]])
    r = np.ones(len(d))
    # (direction, height relative to the radius, angular width² [rad²])
    for c, a, w in [((0, 0.05, 1), 0.45, 0.012), ((1, 0.1, -0.1), 0.16, 0.015),
                    ((-1, 0.1, -0.1), 0.16, 0.015), ((0, 0.5, 0.87), 0.08, 0.06),
                    ((0, -0.45, 0.9), 0.10, 0.04)]:
        c = np.array(c, dtype=np.float64) / np.linalg.norm(c)
        r += a * np.exp(-(1 - d @ c) / w)
    v = d * (4.0 * r)[:, None] * np.array([1.0, 1.2, 1.0])
    faces = []
    ring = lambda i, j: 1 + i * nph + (j % nph)
    for j in range(nph):
        faces.append((0, ring(0, j), ring(0, j + 1)))
        faces.append((len(d) - 1, ring(nt - 2, j + 1), ring(nt - 2, j)))
    for i in range(nt - 2):
        for j in range(nph):
            a_, b_, c_, d_ = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [(a_, c_, b_), (b_, c_, d_)]
    f = np.array(faces)
    lo, hi = v.min(0), v.max(0)
    shift, scale = np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2]), 10.0 / (hi[1] - lo[1])
    v, centre = (v - shift) * scale, -shift * scale
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert (np.einsum("ij,ij->i", fn, v[f].mean(1) - centre) > 0).all(), "faces point outwards"
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, f[:, k], fn)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    with open(path, "w") as out:
        out.write("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in v))
        out.write("".join(f"vn {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in n))
        out.write("".join(f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}\n" for a, b, c in f))

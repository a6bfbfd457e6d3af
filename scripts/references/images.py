#!/usr/bin/env python3
"""`sss render` (every kernel model, and plain Lambertian shading) against Mitsuba 3 on the
built-in sphere scene (`--scene sphere`, the default: a hard shadow on a curved surface), on the
fin scene (`--scene fin`: a sphere and a 3 mm and a 1 mm fin lit from behind, where light reaches
the camera through the fins: plain pre-integration, with `--translucency on`, and the directional
dipole), on a generated bust (`--scene bust`: small features and depth discontinuities) or on the
sphere behind a smooth dielectric boundary (`--scene dielectric`: η = 1.3, lit by a square area
light, which the sphere also mirrors), and the bust and the fins behind the same boundary under a
3 cm light (`--scene bust-dielectric`, `--scene fin-dielectric`).

Mitsuba renders the objects as a homogeneous medium (the material's σa, σs, g per channel) behind
an index-matched `null` boundary, lit by a light it can connect from inside the medium (or, in
the dielectric scene, behind a `dielectric` boundary), on a black floor. Our side uses the same
camera, light and floor, profiles of the scene's η simulated by `sss simulate`, the material's
total diffuse reflectance as albedo, no specular and no ambient light; `sss render` writes
irradiance × albedo, which is π × radiance for a Lambertian surface. The directional dipole (`--method directional-dipole`, no kernel) is rendered as published and
rescaled to the Monte Carlo total reflectance.

Calibration first: the same scene with opaque Lambertian surfaces of that albedo, Mitsuba's
direct light against `sss render --no-sss`, must agree (noise-corrected RMSE ≤ 2 % of the mean,
energy within 1 % per channel), or the scene ranks nothing; a deliberately wrong render (albedo
× 0.8) must fail the same test. Silhouettes and creases (from Mitsuba's shape-index and normal
AOVs) are excluded on both sides of every comparison.

The reference is the mean of two independent Mitsuba renders at half the sample budget each;
their difference measures its noise. Reported per model on 2×2 blocks, relative to the
reference's mean: RMSE, the noise-corrected RMSE (√(MSE − var(reference))) with its standard
error, the spatial part (what remains once each channel is scaled by its best global factor),
SSIM on luminance, the energy ratio per channel, and `sheet.png`: every render beside its
difference from Mitsuba on one labelled colour scale (±20 % of the mean). Rankings compare two
models block by block (paired) and are resolved only when the difference of their
noise-corrected MSEs exceeds 3 standard errors; otherwise they are reported as undecided. What
must hold: no ranking is resolved the wrong way round (every kernel model closer to Mitsuba than
plain Lambertian shading, pre-integration and SVD rank-3 closer than SVD rank-1 — reported, not
required, on the dielectric scene, whose large light leaves the kernels little to do —,
incidence-aware shading closer than pre-integration, exit-angle-aware shading read at the entry
angle closer than incidence-aware alone in structure, each channel scaled by its best factor),
and incidence-aware shading brings every channel's energy ratio within
2 % of 1 (or closer to 1 than pre-integration's). The rescaled directional dipole's
rankings against pre-integration with and without incidence-aware shading are reported, not
required.
"""


import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

from common import budget_lines, material, material_toml, mitsuba, run, sss_binary

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
GATHERS = [("surface-gather-radial", [], [*GATHER_ARGS, "--bssrdf", "radial"]),
           ("surface-gather-directional", [], [*GATHER_ARGS, "--bssrdf", "directional"])]
GATHER_LABELS = [g[0] for g in GATHERS]
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
    ("directional-dipole-mc", [], ["--method", "directional-dipole", "--material", "{material}",
                                   "--profiles", "{profiles}",
                                   "--samples", "32", "--frames", "32", "--light-map", "2048"]),
    *AREA,
    *GATHERS,
]

# Small features and depth discontinuities: the depth tests, the incidence-aware shading.
BUST_MODELS = [m for m in MODELS if m[0] in (
    "lambert", "preint", "preint-reject", "preint-nodepth", "preint-gaussian", "svd1", "svd3",
    "preint-incidence",
    "preint-incidence-exit", "preint-incidence-exit-entry", "preint-incidence-exit-entry-shift", "area-gather",
    *GATHER_LABELS)]

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


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return np.flipud(data).astype(np.float64)


def cube(mi, lo, hi, bsdf, interior=None):
    """A Mitsuba box from its corners [cm]."""
    d = {"type": "cube", "bsdf": bsdf,
         "to_world": mi.ScalarTransform4f().translate([(lo[i] + hi[i]) / 2 for i in range(3)])
         .scale([(hi[i] - lo[i]) / 2 for i in range(3)])}
    if interior:
        d["interior"] = interior
    return d


def scene_dict(mi, m, scene_name, width, height, spp, surface="medium", rho=None, files=None, only=None):
    """The Mitsuba scene: SSS shapes as the material's medium behind an index-matched `null`
    boundary, or a smooth `dielectric` one where the scene has η ≠ 1 (surface="medium"); as an
    opaque Lambertian surface of reflectance rho [R,G,B] lit directly only (surface="direct", the
    calibration of camera, light and geometry) or with every interreflection (surface="diffuse");
    the shape-index AOV that marks silhouettes (surface="aov": shape index and geometric normal);
    or the SSS shapes' coverage (surface="coverage": the shapes emit 1 and nothing else is lit, so
    a pixel holds the fraction of it that sees one). files: paths of generated meshes (scene "bust").
    only: the index of the one SSS shape kept as it is; the others become black occluders that
    still cast their shadows (no light between surfaces)."""
    ch = m["channels"]
    st = [ch[c]["sigma_a_per_cm"] + ch[c]["sigma_s_per_cm"] for c in "RGB"]
    albedo = [ch[c]["sigma_s_per_cm"] / st[i] for i, c in enumerate("RGB")]
    g = ch["R"]["g"]
    sc = SCENES[scene_name]
    eye, target, fov = sc["camera"]
    # RGB values must lie in [0, 1]: σt is given relative to its largest channel.
    medium = lambda: {"type": "homogeneous", "scale": max(st),
                      "sigma_t": {"type": "rgb", "value": [x / max(st) for x in st]},
                      "albedo": {"type": "rgb", "value": albedo},
                      "phase": {"type": "hg", "g": g}}
    black = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}

    eta = sc.get("eta", 1.0)

    def surf(i):
        if only is not None and i != only:
            return {"bsdf": black}
        if surface == "coverage":
            return {"bsdf": black, "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [1, 1, 1]}}}
        if surface == "medium":
            boundary = {"type": "null"} if eta == 1.0 else {"type": "dielectric", "int_ior": eta, "ext_ior": 1.0}
            return {"bsdf": boundary, "interior": medium()}
        return {"bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(rho or [0.5] * 3)}}}
    shapes = {}
    for i, shape in enumerate(sc["media"]):
        if shape[0] == "sphere":
            shapes[f"medium{i}"] = {"type": "sphere", "center": list(shape[1]), "radius": shape[2], **surf(i)}
        elif shape[0] == "obj":
            shapes[f"medium{i}"] = {"type": "obj", "filename": files[shape[1]], "face_normals": False, **surf(i)}
        else:
            s = surf(i)
            shapes[f"medium{i}"] = cube(mi, shape[1], shape[2], s["bsdf"], s.get("interior"))
    for i, (lo, hi) in enumerate(sc["boxes"]):
        shapes[f"occluder{i}"] = cube(mi, lo, hi, black)
    kind, v, *rest = sc["light"]
    if kind == "point":
        light = {"type": "point", "position": list(v), "intensity": {"type": "rgb", "value": [rest[0]] * 3}}
    elif kind == "area":
        # A square of side `side` centred at v facing `aim`: Mitsuba's rectangle spans [−1, 1]² in
        # its local xy plane and emits along local +z, which look_at points at the aim.
        aim, side, radiance = rest
        light = {"type": "rectangle", "bsdf": black,
                 "to_world": mi.ScalarTransform4f().look_at(origin=list(v), target=list(aim), up=[0, 1, 0])
                 .scale([side / 2, side / 2, 1]),
                 **({} if surface == "coverage" else
                    {"emitter": {"type": "area", "radiance": {"type": "rgb", "value": [radiance] * 3}}})}
    elif surface == "coverage":
        light = None
    else:
        power = rest[0]
        n = math.sqrt(sum(x * x for x in v))
        light = {"type": "directional", "direction": [-x / n for x in v],
                 "irradiance": {"type": "rgb", "value": [power] * 3}}
    integrator = {
        # Spectral MIS (volpathmis): a path's distances are sampled from one channel's σt, and
        # plain volpath weights the other channels by ratios of transmittances that grow
        # exponentially along long paths (red fireflies in Skin1); volpathmis weights by the
        # mean of the channels' densities. Measured on the sphere, 96×54, 64 spp: the same mean,
        # per-block noise 16 % → 6.4 % for 1.2× the time. Russian roulette only after 1,000
        # interactions: with Mitsuba's default (5) the medium renders came out 15–20 % brighter
        # (3.9.1, both integrators), against its own deep-roulette renders and our profiles.
        "medium": {"type": "volpathmis", "max_depth": -1, "rr_depth": 1000},
        # Camera → surface → light: one bounce, what `sss render --no-sss` computes.
        "direct": {"type": "path", "max_depth": 2},
        "diffuse": {"type": "path", "max_depth": -1, "rr_depth": 1000},
        "aov": {"type": "aov", "aovs": "si:shape_index,gn:geo_normal"},
        # Emitted light only: what the camera sees first.
        "coverage": {"type": "path", "max_depth": 1},
    }[surface]
    return {
        "type": "scene",
        "integrator": integrator,
        "sensor": {
            "type": "perspective", "fov": fov, "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=list(eye), target=list(target), up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        **shapes,
        "floor": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale([60, 60, 1]),
            "bsdf": black,
        },
        **({"light": light} if light else {}),
    }


def mitsuba_image(mi, scene, seed):
    """An RGB render [width × height × 3] of a scene dict."""
    return np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)[:, :, :3]


def silhouettes(mi, scene):
    """Pixels within one pixel of a boundary between shapes (or of the background) or of a crease,
    from box-filtered AOVs: a pixel's mean shape index is fractional where shapes share it, and its
    mean geometric normal is shorter than 1 where faces of different orientation share it (the
    fins' edges, faces seen edge-on)."""
    aov = np.array(mi.render(mi.load_dict(scene), seed=0), dtype=np.float64)
    si, gn = aov[:, :, 0], aov[:, :, 1:4]
    r = np.round(si)
    edge = (np.abs(si - r) > 1e-3) | ((r > 0) & (np.linalg.norm(gn, axis=2) < 0.98))
    grown = edge.copy()
    p, q = np.pad(r, 1, mode="edge"), np.pad(edge, 1)
    h, w = r.shape
    for dy in range(3):
        for dx in range(3):
            grown |= (p[dy:dy + h, dx:dx + w] != r) | q[dy:dy + h, dx:dx + w]
    return grown


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


def blocks(img, k=2):
    """k×k block averages."""
    h, w, c = img.shape
    return img[: h - h % k, : w - w % k].reshape(h // k, k, w // k, k, c).mean((1, 3))


def block_means(img, k):
    """An image [h × w] shown as its k×k block means (each block's pixels set to their mean)."""
    if k == 1:
        return img
    h, w = img.shape
    b = blocks(img[:, :, None], k)[:, :, 0]
    out = np.zeros_like(img)
    out[: h - h % k, : w - w % k] = np.repeat(np.repeat(b, k, 0), k, 1)
    return out


def ssim(a, b, win=7):
    """Mean SSIM of two luminance images with a win×win box window (Wang et al. 2004)."""
    def box(x):
        c = np.pad(x, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
        return (c[win:, win:] - c[:-win, win:] - c[win:, :-win] + c[:-win, :-win]) / win**2
    L = max(a.max(), b.max(), 1e-12)
    c1, c2 = (0.01 * L) ** 2, (0.03 * L) ** 2
    ma, mb = box(a), box(b)
    va, vb, cov = box(a * a) - ma**2, box(b * b) - mb**2, box(a * b) - ma * mb
    s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma**2 + mb**2 + c1) * (va + vb + c2))
    return float(s.mean())


def write_png(path, rgb):
    """A small PNG writer (8-bit RGB) without extra dependencies."""
    import struct
    import zlib
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].astype(np.uint8).tobytes() for y in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def sheet(path, title, panels, diff_range, diff_label="ours − Mitsuba"):
    """One labelled figure of the comparison: `panels` is a list of (label, image, kind), kind
    "rgb" (8-bit RGB, shown as is) or "diff" (ours − reference, mean of R, G, B, as a fraction of
    the reference's mean), four panels per row under `title`; every difference on one diverging
    scale of ±`diff_range` with its colour bar, which names the difference (`diff_label`)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = 4
    rows = (len(panels) + cols - 1) // cols
    h, w = panels[0][1].shape[:2]
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * h / w * rows + 1.6),
                             squeeze=False, layout="constrained")
    shown = None
    for ax, (label, img, kind) in zip(axes.flat, panels):
        if kind == "diff":
            shown = ax.imshow(100 * img, cmap="RdBu_r", vmin=-100 * diff_range, vmax=100 * diff_range)
        else:
            ax.imshow(img)
        ax.set_title(label, fontsize=9)
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
        if not ax.images:
            ax.axis("off")
    if shown is not None:
        fig.colorbar(shown, ax=axes, orientation="horizontal", shrink=0.5, aspect=40,
                     label=f"{diff_label}, mean of R, G, B [% of the reference's mean]; red: brighter than Mitsuba")
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def tonemap(img, exposure):
    x = np.clip(img * exposure, 0, None)
    t = np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0, 1)
    s = np.where(t <= 0.0031308, 12.92 * t, 1.055 * np.power(t, 1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def measure(o2, r2, d2, mask, mean, do2=None):
    """One image against a reference on 2×2 blocks (o2, r2: block images; d2: the difference of
    the reference's two half-budget renders; mask: the blocks compared; mean: the reference's mean
    there; do2: the same difference for an image that is itself a Monte Carlo estimate, the surface
    gathers). Per block, (o − r̄)² − (r₁ − r₂)²/4 − (o₁ − o₂)²/4 estimates the squared error
    between the noiseless images without bias (var(r̄) = E(r₁ − r₂)²/4): the noise-corrected
    MSE is its mean, with the standard error of that mean, and "resolved" says whether it lies
    more than 3 standard errors above 0. Returns the per-block estimates (for paired comparisons)
    and the summary numbers."""
    noise = d2[mask] ** 2 / 4 + (0 if do2 is None else do2[mask] ** 2 / 4)
    per = ((o2 - r2)[mask] ** 2 - noise).mean(1)
    rmse = float(np.sqrt(((o2 - r2)[mask] ** 2).mean()) / mean)
    mse_c, mse_se = float(per.mean()), float(per.std(ddof=1) / math.sqrt(per.size))
    mean = float(mean)
    rmse_c = math.sqrt(max(mse_c, 0.0)) / mean
    # SE of √MSE by the delta method where the MSE is resolved from 0; else the bound √(3 SE).
    rmse_c_se = mse_se / (2 * math.sqrt(mse_c)) / mean if mse_c > 3 * mse_se else math.sqrt(3 * mse_se) / mean
    # Energy per channel over the blocks, with its standard error from the reference's noise
    # (var Σr̄ = Σ(r₁ − r₂)²/4): what a global factor explains.
    rs = r2[mask].sum(0)
    energy = [float(o2[mask][:, c].sum() / rs[c]) for c in range(3)]
    energy_se = [float(e * math.sqrt((d2[mask][:, c] ** 2 / 4).sum()) / rs[c]) for c, e in enumerate(energy)]
    return per, {"rmse_rel": rmse, "rmse_noise_corrected": rmse_c, "rmse_noise_corrected_se": rmse_c_se,
                 "resolved": bool(mse_c > 3 * mse_se), "energy_ratio": energy, "energy_ratio_se": energy_se}


def score(o2, r2, d2, mask, mean, noise2=None):
    """A model's row of the comparison: measure()'s numbers, plus the attribution (the error left
    once each channel is scaled by its best global factor, by least squares s = Σ o·r̄ / Σ o²,
    which the noise term does not change: the spatial structure; and the share of the
    noise-corrected MSE that factor explains) and SSIM on luminance. noise2: the difference of
    the model's own two half-budget renders, where it is a Monte Carlo estimate. Returns the
    per-block estimates (for paired rankings) and the row."""
    per, row = measure(o2, r2, d2, mask, mean, noise2)
    o, r = o2[mask], r2[mask]
    scale = [float((o[:, c] * r[:, c]).sum() / max((o[:, c] ** 2).sum(), 1e-300)) for c in range(3)]
    _, flat = measure(o2 * np.array(scale), r2, d2, mask, mean,
                      None if noise2 is None else noise2 * np.array(scale))
    row["best_scale"] = scale
    row["rmse_spatial"] = flat["rmse_noise_corrected"]
    row["rmse_spatial_se"] = flat["rmse_noise_corrected_se"]
    total = row["rmse_noise_corrected"] ** 2
    row["energy_share"] = 1 - flat["rmse_noise_corrected"] ** 2 / total if total > 0 else float("nan")
    lum = lambda x: x @ np.array([0.2126, 0.7152, 0.0722])
    row["ssim"] = ssim(lum(o2), lum(r2))
    # Structural dissimilarity, as Maisch & Ropinski report: (1 − SSIM)/2.
    row["dssim"] = (1 - row["ssim"]) / 2
    return per, row


def paired(per_a, per_b):
    """Is a model closer to the truth than another? Paired over blocks (their per-block
    estimates from score()): True/False where the difference of noise-corrected MSEs exceeds 3
    standard errors, else None (undecided)."""
    diff = per_a - per_b
    m, se = diff.mean(), diff.std(ddof=1) / math.sqrt(diff.size)
    return None if abs(m) <= 3 * se else bool(m < 0)


# Calibration tolerance: `sss render --no-sss` against Mitsuba's direct lighting of the same
# opaque Lambertian surfaces, silhouettes masked. Rasterized shadow maps and Mitsuba's exact
# visibility differ along shadow edges by up to a texel, so agreement "within the noise" is
# allowed 2 % of the mean in noise-corrected RMSE (the kernel models differ from each other by
# 1–10 %), and every channel's energy within 1 % (or 3 standard errors, if larger).
CAL_RMSE, CAL_ENERGY = 0.02, 0.01


def calibrated(m):
    """Does a calibration measurement pass?"""
    return bool(m["rmse_noise_corrected"] <= CAL_RMSE and all(
        abs(e - 1) <= max(CAL_ENERGY, 3 * se) for e, se in zip(m["energy_ratio"], m["energy_ratio_se"])))


def error_budget(o2s, gather_noise, alone, r2, d2, mask, rows, shapes, interreflection):
    """Where the image error comes from (issue 30), on the blocks of the comparison, relative to
    the mean of Mitsuba's reference without light between surfaces (`alone`: its two half-budget
    renders): each term's noise-corrected RMSE ± SE and whether it is resolved (> 3 SE above 0).
    - best_realtime: the screen-space method (separable kernels, the area gather) closest to
      that reference, and its error;
    - radial, directional: the surface gathers of the Monte Carlo BSSRDF against it
      (directional: what a half-space BSSRDF, exact for the entry direction, cannot represent:
      curvature, thin parts, several entries);
    - screen_space: the real-time method with the radial gather's own tables (the exit table read
      at the entry angle: a "-exit-entry" model, the closest of them, else best_realtime) ↔
      radial, what the screen-space method loses against the exact integral of the same radial
      profile over the true surface with its visibility;
    - entry_direction: radial ↔ directional, what the entry direction adds;
    - shifted_screen_space: the real-time method with the entry shift (a "-exit-entry-shift"
      model, the closest of them; `shifted_model`) ↔ directional, what it loses against the
      exact half-space BSSRDF over the true surface (absent without such a model);
    - between_surfaces: the full reference ↔ the one without light between surfaces (0 where the
      scene has one SSS shape on a black floor); self_interreflection_lambert: for a Lambertian
      surface of the same albedo, all bounces over direct light, − 1 (what light leaving a concave
      shape and entering it again is worth there; with several shapes it includes the light
      between them). None without both gathers (a run whose --models leaves them out)."""
    if not all(g in o2s for g in GATHER_LABELS):
        return None
    a0, a1 = blocks(alone[0]), blocks(alone[1])
    m0, dm0 = 0.5 * (a0 + a1), a0 - a1
    mean0 = float(m0[mask].mean())
    realtime = [k for k in o2s if k not in GATHER_LABELS and k != "lambert"
                and not k.startswith("directional-dipole") and k != "area-gather-dense"]

    # Every image as (2×2 blocks, the difference of its two half renders or None if noiseless).
    img = {k: (o2s[k], gather_noise.get(k)) for k in o2s}
    reference = (m0, dm0)

    def term(x, y):
        """Image x against image y, both noise-corrected."""
        zero = np.zeros_like(y[0])
        _, row = measure(x[0], y[0], zero if y[1] is None else y[1], mask, mean0, x[1])
        return {k: row[k] for k in ("rmse_noise_corrected", "rmse_noise_corrected_se", "resolved", "energy_ratio")}

    against = {k: term(img[k], reference) for k in realtime}
    best = min(realtime, key=lambda k: against[k]["rmse_noise_corrected"])
    same_tables = [k for k in realtime if k.endswith("-exit-entry")]
    screen = min(same_tables, key=lambda k: against[k]["rmse_noise_corrected"]) if same_tables else best
    shifted = [k for k in realtime if k.endswith("-exit-entry-shift")]
    shifted = min(shifted, key=lambda k: against[k]["rmse_noise_corrected"]) if shifted else None
    full = next(r for r in rows if r["model"] == best)
    radial, directional = GATHER_LABELS
    # The full reference against the one without light between surfaces: both Mitsuba's.
    between = term((r2, d2), reference) if shapes > 1 else ({
        "rmse_noise_corrected": 0.0, "rmse_noise_corrected_se": 0.0, "resolved": False,
        "energy_ratio": [1.0, 1.0, 1.0]})
    return {
        "reference": "Mitsuba without light between surfaces" + (" (one SSS shape: the full reference)" if shapes == 1 else
                                                                   f" ({shapes} SSS shapes rendered alone, summed)"),
        "relative_to": "the mean of that reference over the compared blocks",
        "best_realtime": best,
        "screen_space_model": screen,
        "best_realtime_full_reference": {k: full[k] for k in ("rmse_noise_corrected", "rmse_noise_corrected_se")},
        "terms": {
            "best_realtime": against[best],
            "radial": term(img[radial], reference),
            "directional": term(img[directional], reference),
            "screen_space": term(img[screen], img[radial]),
            "entry_direction": term(img[radial], img[directional]),
            **({"shifted_screen_space": term(img[shifted], img[directional])} if shifted else {}),
            "between_surfaces": between,
        },
        **({"shifted_model": shifted} if shifted else {}),
        "self_interreflection_lambert": [e - 1 for e in interreflection],
        "realtime_against_reference": against,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="CI size: small image, fewer samples")
    ap.add_argument("--material", default="skin1")
    ap.add_argument("--scene", default="sphere", choices=sorted(SCENES),
                    help="sphere (hard shadow, every model), fin (light through thin parts), bust "
                         "(a generated mesh: small features, depth discontinuities), dielectric (the "
                         "sphere behind a smooth η = 1.3 boundary under a 12 cm area light), "
                         "bust-dielectric and fin-dielectric (the bust and the fins behind it under a 3 cm "
                         "light: full size, see docs/measurements.md)")
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    ap.add_argument("--out", default="out/references", help="output folder")
    ap.add_argument("--models", help="comma-separated labels: render only these of the scene's models "
                                     "(and lambert) [default: all]")
    ap.add_argument("--arrays", action="store_true",
                    help="also write arrays.npz: every linear image (radiance), the reference, its two halves, "
                         "the reference without light between surfaces, the compared blocks' mask, the "
                         "calibration's two halves, the silhouette pixels and the albedo ρ (what "
                         "scripts/engines/blender.py scores against)")
    a = ap.parse_args()
    sss = sss_binary(a.sss)
    width, height, spp, photons = (192, 108, 128, 300_000) if a.quick else (384, 216, 1024, 10_000_000)
    # The surface gathers: frames per seed (two seeds), and photons per channel and angle of their
    # angle and directional tables.
    gather_frames, table_photons = (8, 100_000) if a.quick else (64, 1_000_000)
    # Paths that must find the light by chance (behind a dielectric boundary) need more samples.
    spp *= SCENES[a.scene].get("spp_factor", 1)
    # Opaque surfaces lit directly by a point or directional light converge fast: a quarter of
    # the samples. Direct light from an area light is sampled over its surface: all of them.
    cal_spp = spp if SCENES[a.scene]["light"][0] == "area" else max(spp // 4, 16)
    m = material(sss, a.material)
    sc = dict(SCENES[a.scene])
    if a.models:
        keep = set(a.models.split(",")) | {"lambert"}
        unknown = keep - {m[0] for m in sc["models"]}
        if unknown:
            sys.exit(f"--models: {', '.join(sorted(unknown))} not among the {a.scene} scene's models")
        sc["models"] = [m for m in sc["models"] if m[0] in keep]
    name = ("images" if a.scene == "sphere" else f"images-{a.scene}") + (
        "" if a.material == "skin1" else f"-{a.material}")
    out = os.path.join(a.out, name)
    os.makedirs(out, exist_ok=True)
    mi = mitsuba()
    images, gather_noise = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        if any(shape[0] == "obj" for shape in sc["media"]):
            files["bust"] = os.path.join(tmp, "bust.obj")
            bust_obj(files["bust"])
        # The material behind the scene's boundary: index-matched (η = 1) unless the scene says.
        eta = sc.get("eta", 1.0)
        mat = material_toml(m, eta, os.path.join(tmp, "medium.toml"))
        # The calibration's opaque Lambertian surfaces have no dielectric boundary: η = 1 there.
        cal_mat = mat if eta == 1.0 else material_toml(m, 1.0, os.path.join(tmp, "calibration.toml"))
        run([sss, "simulate", mat, "--photons", str(photons), "--profile-only", "--out", tmp])
        summary = json.load(open(os.path.join(tmp, "medium.summary.json")))
        rho = [summary["channels"][c]["rd"] for c in "RGB"]
        profile = os.path.join(tmp, "medium.profile.csv")

        def mitsuba_scene(surface, n, only=None):
            return scene_dict(mi, m, a.scene, width, height, n, surface, rho, files, only)
        # Two independent half-budget renders: their mean is the reference, their difference
        # measures its noise (per 2×2 block, var(mean) = (r₁ − r₂)²/4). The same for the
        # calibration (opaque Lambertian surfaces of reflectance ρ, direct light only), one render
        # with every interreflection, and the shape index that marks silhouettes.
        t0 = time.time()
        ref_a = mitsuba_image(mi, mitsuba_scene("medium", spp // 2), seed=3)
        ref_b = mitsuba_image(mi, mitsuba_scene("medium", spp // 2), seed=4)
        t_ref = time.time() - t0
        # The reference without light between surfaces: each SSS shape alone, the others black
        # occluders that still cast their shadows, the images summed (each pixel sees one shape).
        # With one SSS shape on a black floor it is the reference itself; light that leaves a
        # concave shape and enters it again elsewhere stays in both.
        # Under the small area light (fin-dielectric, full run only) that is three more
        # references' worth of Mitsuba's time.
        several = len(sc["media"]) > 1
        if several:
            t1 = time.time()
            alone = [sum(mitsuba_image(mi, mitsuba_scene("medium", spp // 2, only=i), seed=s + 10 * i)
                         for i in range(len(sc["media"]))) for s in (13, 14)]
            print(f"  Mitsuba: each SSS shape alone ({len(sc['media'])} shapes, {spp} spp each) "
                  f"{time.time() - t1:.0f} s", flush=True)
        else:
            alone = [ref_a, ref_b]
        cal_a = mitsuba_image(mi, mitsuba_scene("direct", cal_spp // 2), seed=5)
        cal_b = mitsuba_image(mi, mitsuba_scene("direct", cal_spp // 2), seed=6)
        gi = mitsuba_image(mi, mitsuba_scene("diffuse", cal_spp), seed=7)
        edge = silhouettes(mi, mitsuba_scene("aov", 16))
        cover = mitsuba_image(mi, mitsuba_scene("coverage", 16), seed=8)
        print(f"  Mitsuba: reference {t_ref:.0f} s ({spp} spp), calibration and AOVs "
              f"{time.time() - t0 - t_ref:.0f} s", flush=True)
        eye, target, fov = sc["camera"]
        kind, v, *rest = sc["light"]
        light = (f"area:{','.join(map(str, v))}:{','.join(map(str, rest[0]))}:{rest[1]}:{rest[2]}" if kind == "area"
                 else f"{kind}:{v[0]},{v[1]},{v[2]}:{rest[0]}")
        common = ["--scene", files.get("bust", sc.get("geometry", a.scene)), "--width", str(width), "--height", str(height),
                  "--camera=" + ",".join(map(str, eye)), "--target=" + ",".join(map(str, target)),
                  "--fov", str(fov),
                  *["--box=" + ":".join(",".join(map(str, c)) for c in box) for box in sc["boxes"]],
                  "--light=" + light, "--floor-albedo", "0,0,0",
                  "--specular", "0", "--ambient", "0", "--albedo", "pre-post"]
        albedo = ["--object-albedo", ",".join(f"{r:.6f}" for r in rho)]
        # The negative control: a deliberately wrong render (albedo × 0.8) the calibration must
        # reject, so the instrument is shown to be able to fail.
        wrong = os.path.join(tmp, "wrong")
        run([sss, "render", *common, "--object-albedo", ",".join(f"{0.8 * r:.6f}" for r in rho),
             "--no-sss", "--material", cal_mat, "--out", wrong])
        wrong = read_pfm(os.path.join(wrong, "render.pfm")) / math.pi
        # The calibration render: `--no-sss` on the same surfaces (the `lambert` model's image
        # where the boundary is index-matched; behind a dielectric one, `lambert` also mirrors the
        # area light, which Mitsuba's opaque Lambertian surfaces do not).
        lambertian = os.path.join(tmp, "calibration")
        run([sss, "render", *common, *albedo, "--no-sss", "--material", cal_mat, "--out", lambertian])
        lambertian = read_pfm(os.path.join(lambertian, "render.pfm")) / math.pi
        for label, fit_args, extra in sc["models"]:
            rdir = os.path.join(tmp, label)
            extra = [x.replace("{material}", mat).replace("{profiles}", tmp).replace("{frames}", str(gather_frames))
                     .replace("{table_photons}", str(table_photons)) for x in extra]
            if label in GATHER_LABELS:
                halves = []
                for seed in (1, 2):
                    run([sss, "render", *common, *albedo, *extra, "--frame-seed", str(seed), "--out", rdir])
                    halves.append(read_pfm(os.path.join(rdir, "render.pfm")) / math.pi)
                images[label] = 0.5 * (halves[0] + halves[1])
                gather_noise[label] = blocks(halves[0]) - blocks(halves[1])
                continue
            # The material names the boundary's η (the mirror image of an area light) to every model.
            if "--material" not in extra:
                extra = [*extra, "--material", mat]
            if fit_args is None:
                run([sss, "render", *common, *albedo, *extra, "--no-sss", "--out", rdir])
            elif not fit_args:
                run([sss, "render", *common, *albedo, *extra, "--out", rdir])
            else:
                # `sss render` lets light through thin parts by default; the models compare
                # with it only where they say so.
                if "--translucency" not in extra:
                    extra = [*extra, "--translucency", "off"]
                kernel = os.path.join(tmp, f"{label}.toml")
                run([sss, "fit", profile, *fit_args, "--taps", "33", "--material", a.material, "--out", kernel])
                run([sss, "render", *common, *albedo, *extra, "--kernel", kernel, "--out", rdir])
            images[label] = read_pfm(os.path.join(rdir, "render.pfm")) / math.pi
    # Errors on 2×2 pixel blocks (Mitsuba's noise averages down, the scattering does not), over
    # the blocks that see an SSS shape, silhouettes excluded (a block with a pixel within one
    # pixel of a boundary between shapes: anti-aliased in Mitsuba, not in ours), relative to the
    # reference's mean there. The blocks are the scene's geometry alone: the same whichever
    # models are compared and however noisy the reference (a mask of the blocks that any image
    # lights grew with the models and with Mitsuba's fireflies in the dark).
    ref = 0.5 * (ref_a + ref_b)
    r2, d2 = blocks(ref), blocks(ref_a) - blocks(ref_b)
    o2s = {k: blocks(v) for k, v in images.items()}
    seen = blocks(cover).sum(2) > 0
    sil = blocks(edge[:, :, None].astype(np.float64))[:, :, 0] > 0
    mask = seen & ~sil
    silhouette_fraction = float((seen & sil).sum() / seen.sum())
    mean = r2[mask].mean()
    # Calibration: our Lambertian image against Mitsuba's direct light on the same opaque
    # surfaces, on the blocks either lights (camera, light and geometry are calibrated where
    # there is direct light; blocks in shadow are 0 in both); and the deliberately wrong render
    # against it.
    c2, dc2 = blocks(0.5 * (cal_a + cal_b)), blocks(cal_a) - blocks(cal_b)
    l2 = blocks(lambertian)
    cal_mask = (c2.sum(2) > 0) | (l2.sum(2) > 0)
    cal_mask &= ~sil
    cal_mean = c2[cal_mask].mean()
    _, cal = measure(l2, c2, dc2, cal_mask, cal_mean)
    _, control = measure(blocks(wrong), c2, dc2, cal_mask, cal_mean)
    cal_ok, control_rejected = calibrated(cal), not calibrated(control)
    # Light that reaches the camera after more than one bounce between the scene's surfaces: no
    # screen-space model adds it.
    interreflection = [float(blocks(gi)[cal_mask][:, c].sum() / c2[cal_mask][:, c].sum()) for c in range(3)]
    noise = float(np.sqrt((d2[mask] ** 2 / 4).mean()) / mean)
    print(f"  {a.scene}, {a.material}: {mask.sum()} blocks compared, silhouettes "
          f"{100 * silhouette_fraction:.1f}% of the lit blocks (excluded)")
    print(f"  reference noise (2×2 blocks, mean of two seeds): {100 * noise:.2f}% of the mean")
    print(f"  calibration (--no-sss against Mitsuba's direct light on Lambertian surfaces): noise-corrected "
          f"RMSE {100 * cal['rmse_noise_corrected']:.2f} ± {100 * cal['rmse_noise_corrected_se']:.2f}% "
          f"(raw {100 * cal['rmse_rel']:.2f}%), energy "
          + "/".join(f"{e:.4f}" for e in cal["energy_ratio"]) + f": {'passes' if cal_ok else 'FAILS'} "
          f"(≤ {100 * CAL_RMSE:.0f}%, energy within {100 * CAL_ENERGY:.0f}%)")
    print(f"  negative control (albedo × 0.8): energy " + "/".join(f"{e:.3f}" for e in control["energy_ratio"])
          + f", RMSE {100 * control['rmse_noise_corrected']:.1f}%: "
          + ("rejected" if control_rejected else "NOT REJECTED"))
    print("  interreflections (all bounces / direct, Lambertian): " + "/".join(f"{e:.4f}" for e in interreflection))
    # The sheet shows each difference from Mitsuba as k×k pixel means, k the smallest of 1, 2, 4
    # and 8 that brings the reference's noise there to 8 % of its mean or below, so a noisy
    # reference's speckle does not hide the models' errors (the numbers use 2×2 blocks).
    shown_k = next((k for k in (1, 2, 4) if noise * 2 / k <= 0.08), 8)
    shown_as = "" if shown_k == 1 else f"\n({shown_k}×{shown_k} px means)"
    rows, per, per_spatial, panels = [], {}, {}, []
    for label, o2 in o2s.items():
        ours = images[label]
        per[label], row = score(o2, r2, d2, mask, mean, gather_noise.get(label))
        # The same per block once each channel is scaled by its best factor: the structure.
        scale, noise2 = np.array(row["best_scale"]), gather_noise.get(label)
        per_spatial[label], _ = measure(o2 * scale, r2, d2, mask, mean, None if noise2 is None else noise2 * scale)
        rows.append({"model": label, **row})
        shown = tonemap(ours, 1.0 / mean / 4)
        write_png(os.path.join(out, f"{label}.png"), shown)
        panels += [(f"{label}:\n{100 * row['rmse_noise_corrected']:.1f} ± "
                    f"{100 * row['rmse_noise_corrected_se']:.1f} %", shown, "rgb"),
                   (f"{label} − Mitsuba{shown_as}", block_means((ours - ref).mean(2) / mean, shown_k), "diff")]
        e = row["energy_ratio"]
        print(f"  {label:<29} noise-corrected RMSE {100 * row['rmse_noise_corrected']:5.2f} ± "
              f"{100 * row['rmse_noise_corrected_se']:4.2f}% (raw {100 * row['rmse_rel']:5.2f}%; "
              f"{100 * row['rmse_spatial']:5.2f}% with the best factor per channel), "
              f"DSSIM {row['dssim']:.4f}, energy {e[0]:.3f}/{e[1]:.3f}/{e[2]:.3f}", flush=True)
    budget = error_budget(o2s, gather_noise, alone, r2, d2, mask, rows, len(sc["media"]), interreflection)
    if a.arrays:
        np.savez_compressed(os.path.join(out, "arrays.npz"), reference=ref, reference_a=ref_a, reference_b=ref_b,
                            alone=0.5 * (alone[0] + alone[1]), mask_blocks=mask,
                            calibration_a=cal_a, calibration_b=cal_b, silhouettes=edge, rho=np.array(rho),
                            **{f"model_{k}": v for k, v in images.items()})
    if budget:
        print("\n".join(budget_lines(budget)))
    write_png(os.path.join(out, "mitsuba.png"), tonemap(ref, 1.0 / mean / 4))
    write_png(os.path.join(out, "mitsuba_lambert.png"), tonemap(gi, 1.0 / mean / 4))
    excluded = np.repeat((255 * (1 - edge))[:, :, None], 3, 2).astype(np.uint8)
    write_png(os.path.join(out, "silhouettes.png"), excluded)
    head = [("Mitsuba (path-traced reference)", tonemap(ref, 1.0 / mean / 4), "rgb"),
            ("silhouettes and creases (black: excluded)", excluded, "rgb"),
            ("calibration: --no-sss, Lambertian surfaces", tonemap(lambertian, 1.0 / cal_mean / 4), "rgb"),
            ("calibration − Mitsuba's direct light", (lambertian - 0.5 * (cal_a + cal_b)).mean(2) / cal_mean, "diff")]
    if several:
        m0 = 0.5 * (alone[0] + alone[1])
        head += [("Mitsuba, SSS shapes alone", tonemap(m0, 1.0 / mean / 4), "rgb"),
                 (f"between surfaces: full − alone{shown_as}", block_means((ref - m0).mean(2) / mean, shown_k),
                  "diff")]
    sheet(os.path.join(out, "sheet.png"),
          f"{a.scene} / {a.material}, {width}×{height}, Mitsuba {spp} spp (noise {100 * noise:.1f} % per 2×2 block)\n"
          f"each model's noise-corrected RMSE ± SE (% of the reference's mean)",
          head + panels, 0.2)

    def closer(a, b):
        return paired(per[a], per[b])

    def pair(a, b):
        return a in o2s and b in o2s

    checks = {"calibration passes": cal_ok, "negative control (albedo × 0.8) rejected": control_rejected}
    ranked = {}
    # A scene that fails calibration is not used to compare models.
    if cal_ok:
        # The kernels' shapes: each closer than Lambertian shading, pre-integration and SVD rank-3
        # closer than SVD rank-1 (required where the scene says so, else reported).
        kernels = {f"{k} closer than lambert": closer(k, "lambert") for k in o2s if k != "lambert" and "-" not in k}
        for a_, b_, name in [("preint", "svd1", "preint closer than svd1"), ("svd3", "svd1", "svd3 closer than svd1")]:
            if pair(a_, b_):
                kernels[name] = closer(a_, b_)
        # The physics around the kernel (always required): incidence-aware shading closer than
        # plain pre-integration; the exit law read at the entry angle closer than incidence-aware
        # shading alone in structure (each channel at its best factor). The exit law moves light
        # between view angles; where the half-space models lack light for other reasons (the
        # budget's directional term: the bust's convex features, Marble's long paths), its
        # full error can grow although the structure improves, and the normal-entry law is the
        # wrong one at oblique entry (Chandrasekhar's H(μ)/(μ + μ₀)): both reported below.
        if pair("preint-incidence", "preint"):
            ranked["incidence-aware closer than preint"] = closer("preint-incidence", "preint")
        for a_, b_, name in [("preint-incidence-exit-entry", "preint-incidence",
                              "exit-aware (entry angle) closer than incidence-aware in structure"),
                             ("preint-incidence-translucency-exit-entry", "preint-incidence-translucency",
                              "exit-aware (entry angle) closer than incidence-aware in structure (with translucency)")]:
            if pair(a_, b_):
                ranked[name] = paired(per_spatial[a_], per_spatial[b_])
        if sc.get("kernel_order", True):
            ranked.update(kernels)
        # Energy is a sum over thousands of pixels, far less noisy than the RMSE: with
        # incidence-aware shading every channel's energy ratio must lie within 2 % of 1 (issue
        # 15's goal) or at least closer to 1 than plain pre-integration's.
        e = {x["model"]: x["energy_ratio"] for x in rows}
        if pair("preint-translucency", "preint"):
            # Light through the fins is light plain screen-space shading misses entirely.
            checks["translucency energy closer to Mitsuba than preint"] = all(
                abs(e["preint-translucency"][c] - 1) < abs(e["preint"][c] - 1) for c in range(3))
        if pair("preint-incidence", "preint"):
            checks["incidence-aware energy within 2 % of Mitsuba or closer than preint"] = all(
                abs(e["preint-incidence"][c] - 1) < max(0.02, abs(e["preint"][c] - 1)) for c in range(3))
        # The entry shift (`--entry-shift`) is the directional gather's anisotropy in real time:
        # required to bring the real-time method closer where the exact half-space BSSRDF is
        # resolved closer than the radial profile (the bust's and the fins' grazing entry),
        # reported elsewhere (the sphere, where the half-space's forward transport overshoots
        # at the terminator, the directional gather farther than the radial one).
        directional_helps = pair(*GATHER_LABELS[::-1]) and closer(GATHER_LABELS[1], GATHER_LABELS[0]) is True
        shift_pairs = [("preint-incidence-exit-entry-shift", "preint-incidence-exit-entry"),
                       ("preint-incidence-translucency-exit-entry-shift", "preint-incidence-translucency-exit-entry")]
        if directional_helps:
            for a_, b_ in shift_pairs:
                if pair(a_, b_):
                    ranked[f"{a_} closer than {b_} (the directional gather closer than the radial)"] = closer(a_, b_)
        # A ranking fails only where it is resolved the wrong way round.
        checks.update({k: v is not False for k, v in ranked.items()})
        if not directional_helps:
            for a_, b_ in shift_pairs:
                if pair(a_, b_):
                    ranked[f"{a_} closer than {b_}"] = closer(a_, b_)
        # Reported, not required: the best real-time methods against each other.
        if not sc.get("kernel_order", True):
            ranked.update(kernels)
        for a_, b_ in [("preint-incidence-exit", "preint-incidence"),
                       ("preint-incidence-exit-entry", "preint-incidence"),
                       ("preint-incidence-translucency-exit", "preint-incidence-translucency"),
                       ("preint-incidence-exit-entry", "preint-incidence-exit"),
                       ("preint-incidence-translucency-exit-entry", "preint-incidence-translucency-exit"),
                       ("directional-dipole-mc", "preint-incidence"), ("directional-dipole-mc", "preint"),
                       ("preint-translucency", "preint"), ("preint-incidence-translucency", "preint"),
                       ("directional-dipole-mc", "preint-incidence-translucency"),
                       ("preint-reject", "preint"), ("preint-nodepth", "preint"),
                       ("preint-gaussian", "preint"), ("preint-gaussian", "preint-reject"),
                       ("area-gather", "preint"), ("area-gather", "area-gather-dense"),
                       ("area-gather-incidence-exit", "preint-incidence-exit"),
                       ("area-gather", "preint-translucency"), ("area-gather", "directional-dipole-mc")]:
            if pair(a_, b_):
                ranked[f"{a_} closer than {b_}"] = closer(a_, b_)
    # How much of plain pre-integration's error the angular dependence of total reflectance
    # (incidence-aware shading) removes: the share of its noise-corrected MSE.
    incidence_share = None
    if pair("preint-incidence", "preint"):
        p_, i_ = per["preint"].mean(), per["preint-incidence"].mean()
        incidence_share = float(1 - i_ / p_) if p_ > 0 else None
    ok = all(checks.values())
    with open(os.path.join(out, "images.json"), "w") as f:
        json.dump({"scene": a.scene, "material": a.material, "width": width, "height": height, "spp": spp,
                   "reference_noise_rel": noise, "silhouette_fraction": silhouette_fraction,
                   "calibration_rmse_rel": cal["rmse_noise_corrected"],
                   "calibration_rmse_se": cal["rmse_noise_corrected_se"],
                   "calibration_rmse_raw": cal["rmse_rel"],
                   "calibration_energy_ratio": cal["energy_ratio"],
                   "calibration_pass": cal_ok,
                   "calibration_tolerance": {"rmse_rel": CAL_RMSE, "energy": CAL_ENERGY},
                   "negative_control": {"what": "--no-sss with the albedo × 0.8",
                                        "energy_ratio": control["energy_ratio"],
                                        "rmse_rel": control["rmse_noise_corrected"], "rejected": control_rejected},
                   "interreflection_ratio": interreflection,
                   "incidence_share_of_preint_mse": incidence_share,
                   "models": rows, "rankings": ranked, "checks": checks, "pass": ok,
                   **({"error_budget": budget} if budget else {})}, f, indent=2)
    for k, v in ranked.items():
        print(f"  {k}: {'yes' if v else 'undecided (within 3 SE)' if v is None else 'NO'}")
    for k, v in checks.items():
        if not v:
            print(f"  FAILED: {k}")
    print(f"images: {'agree' if ok else 'DISAGREE'} ({sum(checks.values())}/{len(checks)} checks) → {out}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

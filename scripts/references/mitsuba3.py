"""Mitsuba 3's side of the image comparisons: the variant to load, each scene as a Mitsuba scene
dict (the SSS shapes as a homogeneous medium, or the opaque Lambertian surfaces of the
calibration, the AOVs that mark silhouettes, the coverage of the SSS shapes), and every render one
comparison needs (`render_references`). Lengths are in centimetres; images are linear radiance,
[height × width × 3] arrays of float64."""

import math
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from references.scenes import SCENES

# Debian's libllvm19 (bookworm main), which Dr.Jit's LLVM backend loads.
LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


def mitsuba(vectorised=False):
    """Mitsuba 3. With `vectorised`, the llvm_ad_rgb variant where Debian's libllvm19 is installed:
    on profiles.py's radiance meter it is 3× faster than scalar_rgb here (81 s against about 6 min
    for --quick), and its standard errors came out about half as large at equal samples (why is not
    traced). On images.py's scenes it is not faster (sphere 46 s against 35 s, dielectric 199 s
    against 183 s: paths of very different lengths leave most SIMD lanes idle), so images stay
    scalar. Otherwise scalar_rgb, which works from the wheel as is. SSS_MITSUBA_VARIANT overrides
    the choice."""
    variant = os.environ.get("SSS_MITSUBA_VARIANT")
    if variant is None:
        variant = "llvm_ad_rgb" if vectorised and os.path.exists(LIBLLVM) else "scalar_rgb"
    if variant.startswith("llvm"):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", LIBLLVM)
    try:
        import mitsuba as mi
    except ImportError:
        sys.exit("Mitsuba 3 is not installed: pip install -r scripts/references/requirements.txt")
    mi.set_variant(variant)
    return mi


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
    # The whole scene moved so that what the camera looks at lies at the origin. Mitsuba 3.9's
    # ray epsilon grows with the coordinates, (1 + max|p|)·ε, and light entering or leaving a
    # medium within it is lost: a flat Skin1 half-space against Chandrasekhar's exact reflectance
    # reads −0.2 / −0.6 / −1.5 % (R / G / B) with its surface 10 cm from the origin, −3.2 % in B
    # at 20 cm, −15 % at 100 cm, and is exact (within 0.2 %) at the origin (docs/measurements.md).
    def at(p):
        return [p[k] - target[k] for k in range(3)]
    moved = mi.ScalarTransform4f().translate(at([0.0, 0.0, 0.0]))
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
            shapes[f"medium{i}"] = {"type": "sphere", "center": at(shape[1]), "radius": shape[2], **surf(i)}
        elif shape[0] == "obj":
            shapes[f"medium{i}"] = {"type": "obj", "filename": files[shape[1]], "face_normals": False,
                                    "to_world": moved, **surf(i)}
        else:
            s = surf(i)
            shapes[f"medium{i}"] = cube(mi, at(shape[1]), at(shape[2]), s["bsdf"], s.get("interior"))
    for i, (lo, hi) in enumerate(sc["boxes"]):
        shapes[f"occluder{i}"] = cube(mi, at(lo), at(hi), black)
    kind, v, *rest = sc["light"]
    if kind == "point":
        light = {"type": "point", "position": at(v), "intensity": {"type": "rgb", "value": [rest[0]] * 3}}
    elif kind == "area":
        # A square of side `side` centred at v facing `aim`: Mitsuba's rectangle spans [−1, 1]² in
        # its local xy plane and emits along local +z, which look_at points at the aim.
        aim, side, radiance = rest
        light = {"type": "rectangle", "bsdf": black,
                 "to_world": mi.ScalarTransform4f().look_at(origin=at(v), target=at(aim), up=[0, 1, 0])
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
            "to_world": mi.ScalarTransform4f().look_at(origin=at(eye), target=at(target), up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        **shapes,
        "floor": {
            "type": "rectangle",
            "to_world": moved @ mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale([60, 60, 1]),
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


@dataclass
class References:
    """Mitsuba's renders of one comparison, each [height × width × 3] linear radiance unless
    said otherwise."""
    ref_a: np.ndarray      # the reference's first half-budget render (SSS shapes as the medium)
    ref_b: np.ndarray      # its second, an independent seed: the mean is the reference
    alone: list            # the two halves without light between surfaces (ref_a, ref_b with one SSS shape)
    cal_a: np.ndarray      # the calibration's first half: opaque Lambertian surfaces, direct light only
    cal_b: np.ndarray      # its second half
    gi: np.ndarray         # the same surfaces with every interreflection
    edge: np.ndarray       # silhouette and crease pixels [height × width], bool
    cover: np.ndarray      # the SSS shapes' coverage (1 where a pixel sees one only)
    several: bool          # whether the scene holds more than one SSS shape


def render_references(mi, m, setup, rho, files):
    """Every Mitsuba render of one comparison (Setup `setup`, material `m` as `sss materials`
    gives it, Lambertian reflectance `rho` [R, G, B] for the calibration, generated meshes
    `files`), with their times printed."""
    def mitsuba_scene(surface, n, only=None):
        return scene_dict(mi, m, setup.name, setup.width, setup.height, n, surface, rho, files, only)
    spp, cal_spp, media = setup.spp, setup.cal_spp, setup.scene["media"]
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
    several = len(media) > 1
    if several:
        t1 = time.time()
        alone = [sum(mitsuba_image(mi, mitsuba_scene("medium", spp // 2, only=i), seed=s + 10 * i)
                     for i in range(len(media))) for s in (13, 14)]
        print(f"  Mitsuba: each SSS shape alone ({len(media)} shapes, {spp} spp each) "
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
    return References(ref_a, ref_b, alone, cal_a, cal_b, gi, edge, cover, several)

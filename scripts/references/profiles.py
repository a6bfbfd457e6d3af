#!/usr/bin/env python3
"""Rd(r) of `sss simulate` (MCML physics) against Mitsuba 3's volumetric path tracer.

Mitsuba cannot connect a collimated beam seen through a smooth dielectric, so the measurement
runs backwards (reciprocity): a radiance meter looks straight down at the origin of a half-space
(a cube 400 mean free paths wide with a `dielectric` boundary of the material's η and a
homogeneous medium with its σt, albedo and HG g), lit by a Lambertian annulus emitter of unit
radiance just above the surface covering r0 ≤ r < r1. The meter then reads ∫ Rd(r) dA over the
annulus (angle-integrated, without Rsp: exactly what MCML bins). The reading depends linearly on
the emitter's height h; two heights with the same seeds give the limit h → 0 as 2·L(h) − L(2h).
Mitsuba's error comes from K independent seeds; MC's from the profile's standard errors. The
comparison is a χ² over bins with both errors, r in [0.1, 5] mean free paths (1/σt).
"""

import argparse
import json
import math
import os
import sys
import tempfile

if not __package__:
    # Run by path (`python3 scripts/references/profiles.py`): Python puts this folder on sys.path, not
    # the one that holds the `references` package.
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import numpy as np  # noqa: E402

from references.mitsuba3 import mitsuba  # noqa: E402
from references.ours import material, read_profile, run, sss_binary  # noqa: E402


def annulus_obj(r0, r1, z, seg=256):
    """A flat annulus at height z facing down (−z), as OBJ text."""
    out = []
    for k in range(seg):
        a = 2 * math.pi * k / seg
        out.append(f"v {r0 * math.cos(a)} {r0 * math.sin(a)} {z}")
        out.append(f"v {r1 * math.cos(a)} {r1 * math.sin(a)} {z}")
    out.append("vn 0 0 -1")
    for k in range(seg):
        i0, o0 = 2 * k + 1, 2 * k + 2
        i1, o1 = 2 * ((k + 1) % seg) + 1, 2 * ((k + 1) % seg) + 2
        out.append(f"f {i0}//1 {i1}//1 {o0}//1")
        out.append(f"f {o0}//1 {i1}//1 {o1}//1")
    return "\n".join(out) + "\n"


def polygon_annulus_area(r0, r1, seg=256):
    """Area of the 256-gon annulus (what the emitter covers)."""
    return 0.5 * seg * math.sin(2 * math.pi / seg) * (r1 * r1 - r0 * r0)


def mitsuba_annulus(mi, sigma_a, sigma_s, g, eta, r0, r1, heights, spp, seeds, tmp):
    """∫_annulus Rd dA extrapolated to zero emitter height: (mean, standard error)."""
    st = sigma_a + sigma_s
    half = 200.0 / st
    readings = []
    scenes = []
    for h in heights:
        path = os.path.join(tmp, f"ring_{r0:.6g}_{h:.6g}.obj")
        with open(path, "w") as f:
            f.write(annulus_obj(r0, r1, h))
        scenes.append(mi.load_dict({
            "type": "scene",
            "integrator": {"type": "volpath", "max_depth": -1, "rr_depth": 1000},
            "sensor": {
                "type": "radiancemeter", "origin": [0, 0, 0.5 * heights[0]], "direction": [0, 0, -1],
                "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"},
                         "pixel_format": "rgb"},
                "sampler": {"type": "independent", "sample_count": 1},
            },
            "slab": {
                "type": "cube",
                "to_world": mi.ScalarTransform4f().translate([0, 0, -half]).scale([half, half, half]),
                "bsdf": {"type": "dielectric", "int_ior": eta, "ext_ior": 1.0},
                "interior": {"type": "homogeneous", "sigma_t": st, "albedo": sigma_s / st,
                             "phase": {"type": "hg", "g": g}},
            },
            "ring": {"type": "obj", "filename": path,
                     "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 1.0}}},
        }))
    for k in range(seeds):
        v = [float(np.array(mi.render(s, spp=spp // seeds, seed=1000 + k))[0, 0, 0]) for s in scenes]
        readings.append(2.0 * v[0] - v[1])
    mean = sum(readings) / seeds
    var = sum((x - mean) ** 2 for x in readings) / (seeds - 1)
    # The polygon covers slightly less than the annulus: scale to the true annulus area.
    scale = math.pi * (r1 * r1 - r0 * r0) / polygon_annulus_area(r0, r1)
    return mean * scale, math.sqrt(var / seeds) * scale


def mc_annulus(dr, rows, c, r0, r1):
    """∫_annulus Rd dA from the MC profile, whole bins (edges snapped to the grid)."""
    i0, i1 = round(r0 / dr), round(r1 / dr)
    mass = sum(rows[i][1][c] * math.pi * (2 * i + 1) * dr * dr for i in range(i0, i1))
    var = sum((rows[i][2][c] * math.pi * (2 * i + 1) * dr * dr) ** 2 for i in range(i0, i1))
    return mass, math.sqrt(var), i0 * dr, i1 * dr


def compare(sss, name, channels, bins, spp, seeds, photons, tmp):
    """Material `name`'s Rd(r) from `sss simulate` (`photons` per channel) against Mitsuba's, on
    `bins` annuli per channel of `channels` (e.g. "RGB"), log-spaced over [0.1, 5] mean free
    paths, each Mitsuba reading `spp` samples over `seeds` seeds; files go to `tmp`. Returns one
    row per annulus (radii in mean free paths, ∫ Rd dA and its SE, the z-score), printed too."""
    m = material(sss, name)
    run([sss, "simulate", name, "--photons", str(photons), "--profile-only", "--out", tmp,
         "--seed", "7"])
    dr, rows = read_profile(os.path.join(tmp, f"{name}.profile.csv"))
    mi = mitsuba(vectorised=True)
    results = []
    for ch in channels:
        c = "RGB".index(ch)
        p = m["channels"][ch]
        sa, ss, g, eta = p["sigma_a_per_cm"], p["sigma_s_per_cm"], p["g"], m["eta"]
        mfp = 1.0 / (sa + ss)
        edges = [0.1 * mfp * (50.0 ** (k / bins)) for k in range(bins + 1)]
        for k in range(bins):
            mass, mass_se, a, b = mc_annulus(dr, rows, c, edges[k], edges[k + 1])
            if b <= a:
                continue
            heights = (0.01 * mfp, 0.02 * mfp)
            ref, ref_se = mitsuba_annulus(mi, sa, ss, g, eta, a, b, heights, spp, seeds, tmp)
            z = (ref - mass) / math.hypot(ref_se, mass_se)
            results.append({"material": name, "channel": ch, "r0_mfp": a / mfp, "r1_mfp": b / mfp,
                            "mc": mass, "mc_se": mass_se, "mitsuba": ref, "mitsuba_se": ref_se,
                            "rel_diff": (ref - mass) / mass, "z": z})
            print(f"  {name} {ch} r {a / mfp:5.2f}–{b / mfp:5.2f} MFP: MC {mass:.5f} ± {mass_se:.5f}, "
                  f"Mitsuba {ref:.5f} ± {ref_se:.5f} ({100 * (ref - mass) / mass:+.2f}%, z {z:+.2f})",
                  flush=True)
    return results


def main():
    """Compares the cases asked for, writes OUT/profiles.json; 0 where they agree."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="CI size: Skin1 only, fewer samples")
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    ap.add_argument("--out", default="out/references", help="output folder for profiles.json")
    ap.add_argument("--materials", help="comma-separated NAME:CHANNELS, e.g. marble:R,soymilk:RGB "
                    "[default: skin1:RB with --quick, else skin1, marble and soymilk, all channels]")
    a = ap.parse_args()
    sss = sss_binary(a.sss)
    if a.quick:
        cases = [("skin1", "RB")]
        bins, spp, seeds, photons = 6, 144000, 16, 1_000_000
    else:
        # Skin1 (η 1.3), Marble (η 1.5), a Narasimhan liquid with g > 0.8 (soy milk, g 0.83–0.87).
        cases = [("skin1", "RGB"), ("marble", "RGB"), ("soymilk", "RGB")]
        bins, spp, seeds, photons = 10, 400000, 16, 10_000_000
    if a.materials:
        cases = [tuple(c.split(":")) if ":" in c else (c, "RGB") for c in a.materials.split(",")]
    os.makedirs(a.out, exist_ok=True)
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, channels in cases:
            results += compare(sss, name, channels, bins, spp, seeds, photons, tmp)
    chi2 = sum(r["z"] ** 2 for r in results)
    dof = len(results)
    worst = max(abs(r["z"]) for r in results)
    ok = chi2 / dof < 2.0 and worst < 4.0
    summary = {"chi2": chi2, "dof": dof, "max_abs_z": worst, "pass": ok, "bins": results}
    with open(os.path.join(a.out, "profiles.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(f"profiles: χ²/dof = {chi2:.1f}/{dof} = {chi2 / dof:.2f}, max |z| = {worst:.2f} → "
          f"{'agree' if ok else 'DISAGREE'} (pass: χ²/dof < 2 and every |z| < 4)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

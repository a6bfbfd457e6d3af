#!/usr/bin/env python3
"""Regenerates every Mitsuba 3 reference and prints one table of the image comparisons: Rd(r)
profiles (profiles.py), then images (images.py) of each scene and material: scene × material ×
model, the noise-corrected error ± its standard error, SSIM and the energy ratio per channel,
after each scene's calibration. --quick is the CI size (Skin1 on the sphere, fin and bust scenes;
about 9 minutes on 2 cores); without it, the full version (larger images, more samples, Skin1,
Marble, Ketchup and Whole milk, the sphere behind a dielectric boundary under an area light, and
the bust and the fins behind it under a 3 cm light; hours). `images.py --scene dielectric
--material skin1 --quick` runs the dielectric sphere at CI size alone (about 5 minutes). Where Blender's Python module is installed
(scripts/engines/requirements.txt), every sphere, fin and bust comparison is followed by
scripts/engines/blender.py scene on the same reference: Cycles' random walk and Christensen–Burley
with `sss engine-params`' fields (about 15 s a scene at --quick), and without --quick EEVEE too
(about 2 minutes a scene on Mesa's software OpenGL); their rows join images.json. The full run
ends each Skin1 scene (sphere, fins, bust) with pareto.py: every real-time method's frame time at
1920×1080 against its error, pareto.png beside sheet.png (about 15 minutes a scene on lavapipe;
timings need an otherwise idle machine, so CI's quick run leaves them out). Exits non-zero
when an agreement test or a calibration fails. Outputs: OUT/profiles.json, OUT/images*/images.json
and their PNGs (blender-sheet.png beside sheet.png), OUT/summary.json."""

import argparse
import importlib.util
import json
import os
import subprocess
import sys

if not __package__:
    # Run by path (`python3 scripts/references/run.py`): Python puts this folder on sys.path, not
    # the one that holds the `references` package.
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from references.budget import budget_lines  # noqa: E402
from references.scenes import folder  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


# (scene, material) pairs: the sphere's hard shadow, the fins lit from behind, the bust's small
# features, the sphere behind a dielectric boundary under an area light; short (Skin1, Ketchup)
# and long (Marble, Whole milk) mean free paths.
# The dielectric sphere (its area light through a dielectric boundary needs 384 spp: 5 of the
# quick run's 14 minutes) is in the full run only, which keeps CI under 30 minutes.
QUICK = [("sphere", "skin1"), ("fin", "skin1"), ("bust", "skin1")]
FULL = QUICK + [("dielectric", "skin1"), ("sphere", "marble"), ("sphere", "ketchup"),
                ("sphere", "wholemilk"), ("fin", "marble"), ("bust", "marble"), ("dielectric", "marble"),
                ("bust-dielectric", "skin1"), ("fin-dielectric", "skin1")]


def table(results):
    """One line per scene × material × model; the calibration above each scene's block."""
    lines = []
    for (scene, mat), r in results:
        e = r["calibration_energy_ratio"]
        lines.append(f"{scene} / {mat}: calibration {100 * r['calibration_rmse_rel']:.2f} ± "
                     f"{100 * r['calibration_rmse_se']:.2f} %, energy {e[0]:.3f}/{e[1]:.3f}/{e[2]:.3f} "
                     f"({'passes' if r['calibration_pass'] else 'FAILS: not used'}); reference noise "
                     f"{100 * r['reference_noise_rel']:.1f} % per 2×2 block")
        if not r["calibration_pass"]:
            continue
        w = max(30, *(len(m["model"]) for m in r["models"]))
        lines.append(f"  {'model':<{w}} {'error (noise-corrected)':>24} {'spatial':>8} {'SSIM':>7}  energy R/G/B")
        for m in r["models"]:
            e = m["energy_ratio"]
            lines.append(f"  {m['model']:<{w}} {100 * m['rmse_noise_corrected']:>14.2f} ± {100 * m['rmse_noise_corrected_se']:4.2f} %"
                         f" {100 * m['rmse_spatial']:>6.2f} % {m['ssim']:>7.4f}  {e[0]:.3f}/{e[1]:.3f}/{e[2]:.3f}")
        if r.get("error_budget"):
            lines += budget_lines(r["error_budget"])
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    ap.add_argument("--out", default="out/references")
    ap.add_argument("--blender", choices=["auto", "on", "off"], default="auto",
                    help="Blender's renderers on the same references: auto (where bpy is installed), on, off")
    a = ap.parse_args()
    extra = (["--quick"] if a.quick else []) + (["--sss", a.sss] if a.sss else []) + ["--out", a.out]
    blender = a.blender == "on" or (a.blender == "auto" and importlib.util.find_spec("bpy") is not None)
    print(f"Blender's renderers: {'on' if blender else 'off (bpy is not installed)' if a.blender == 'auto' else 'off'}")
    renderers = "blender-cycles-random-walk,blender-cycles-burley" + ("" if a.quick else ",blender-eevee")
    failed, results = [], []
    jobs = [("profiles.py", [], None)] + [
        ("images.py", ["--scene", sc, "--material", mat], (sc, mat)) for sc, mat in (QUICK if a.quick else FULL)]
    for script, args, key in jobs:
        name = " ".join([script, *args])
        print(f"== {name}", flush=True)
        # blender.py builds the index-matched scenes (its area lights and dielectric boundary are not built).
        arrays = ["--arrays"] if key and blender and "dielectric" not in key[0] else []
        if subprocess.run([sys.executable, os.path.join(HERE, script), *args, *extra, *arrays]).returncode != 0:
            failed.append(name)
        if arrays:
            engines = os.path.join(HERE, "..", "engines", "blender.py")
            print(f"== blender.py scene {' '.join(args)}", flush=True)
            if subprocess.run([sys.executable, engines, *(["--sss", a.sss] if a.sss else []), "scene", *args,
                               "--out", a.out, "--renderers", renderers]).returncode != 0:
                failed.append(f"blender.py scene {' '.join(args)}")
        if key and not a.quick and key in QUICK:
            print(f"== pareto.py {' '.join(args)}", flush=True)
            if subprocess.run([sys.executable, os.path.join(HERE, "pareto.py"), *args, *extra]).returncode != 0:
                failed.append(f"pareto.py {' '.join(args)}")
        if key:
            sc, mat = key
            path = os.path.join(a.out, folder(sc, mat), "images.json")
            if os.path.exists(path):
                results.append((key, json.load(open(path))))
    print("\n== images: scene / material: calibration against Mitsuba's direct light, then each model's "
          "error against the path-traced reference (% of its mean; spatial: once each channel is scaled "
          "by its best global factor)")
    print(table(results))
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump({"failed": failed, "images": [{"scene": k[0], "material": k[1], **r} for k, r in results]},
                  f, indent=2)
    print("references: " + ("all agree" if not failed else "FAILED " + ", ".join(failed)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

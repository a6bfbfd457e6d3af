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
import os
import sys
import tempfile

if not __package__:
    # Run by path (`python3 scripts/references/images.py`, as run.py and the docs do): Python puts
    # this folder on sys.path, not the one that holds the `references` package.
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import numpy as np  # noqa: E402

from references import halfspace, scenes  # noqa: E402
from references.budget import budget_lines, error_budget  # noqa: E402
from references.mitsuba3 import mitsuba, render_references  # noqa: E402
from references.ours import material, render_ours, scene_view, simulate_medium, sss_binary  # noqa: E402
from references.rankings import incidence_share, rank  # noqa: E402
from references.scoring import (CAL_ENERGY, CAL_RMSE, calibrate, compare_blocks,  # noqa: E402
                                print_calibration, score_models)
from references.sheets import model_panels, shown_block_size, write_sheet  # noqa: E402


def parser():
    """The command line."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="CI size: small image, fewer samples")
    ap.add_argument("--material", default="skin1")
    ap.add_argument("--scene", default="sphere", choices=sorted(scenes.SCENES),
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
                         "scripts/engines/blender.py scores against), and view.json: the scene as `sss render` "
                         "drew it, for `sss view --reference OUT/SCENE` to show the reference beside the page")
    return ap


def render_all(sss, mi, m, setup):
    """Every render of one comparison, Mitsuba's and ours, in a temporary folder (the generated
    mesh, the material files, the profiles, the kernels): (mitsuba3.References, ours.Renders,
    the albedo ρ [R, G, B], the view: `ours.scene_view` with the albedo, the material file's text
    and the generated mesh's)."""
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        if any(shape[0] == "obj" for shape in setup.scene["media"]):
            files["bust"] = os.path.join(tmp, "bust.obj")
            scenes.bust_obj(files["bust"])
        # The material behind the scene's boundary: index-matched (η = 1) unless the scene says.
        medium = simulate_medium(sss, m, setup.scene.get("eta", 1.0), setup.photons, tmp)
        refs = render_references(mi, m, setup, medium.rho, files)
        renders = render_ours(sss, setup, files, medium, tmp)
        with open(medium.toml) as f:
            view = {"name": setup.name, **scene_view(setup, files), "object_albedo": list(medium.rho),
                    "material_toml": f.read()}
        if "bust" in files:
            with open(files["bust"]) as f:
                view["mesh_obj"] = f.read()
    return refs, renders, medium.rho, view


def write_view(out, view):
    """view.json (--arrays): the scene as `sss render` drew it and its material, for `sss view
    --reference OUT` to draw the page's view of it beside the reference; a generated mesh is
    written beside it (bust.obj) and named relative to the folder."""
    view = dict(view)
    mesh = view.pop("mesh_obj", None)
    if mesh is not None:
        with open(os.path.join(out, "bust.obj"), "w") as f:
            f.write(mesh)
        view["scene"] = "bust.obj"
    with open(os.path.join(out, "view.json"), "w") as f:
        json.dump(view, f, indent=2)


def write_arrays(path, refs, renders, comparison, rho):
    """arrays.npz (--arrays): every linear image, the reference and its halves, the reference
    without light between surfaces, the compared blocks, the calibration's halves, the silhouette
    pixels and the albedo ρ, what scripts/engines/blender.py scores against."""
    np.savez_compressed(path, reference=comparison.ref, reference_a=refs.ref_a, reference_b=refs.ref_b,
                        alone=0.5 * (refs.alone[0] + refs.alone[1]), mask_blocks=comparison.mask,
                        calibration_a=refs.cal_a, calibration_b=refs.cal_b, silhouettes=refs.edge, rho=np.array(rho),
                        **{f"model_{k}": v for k, v in renders.images.items()})


# How far the scenes' visible surfaces lie from the origin, about (each Mitsuba scene is centred on
# what its camera looks at): where the medium check's second patch lies [cm].
MEDIUM_CHECK_OFFSET = 5.0


def print_medium_check(medium):
    """One line on the medium check (`halfspace.check`), or none where it does not apply."""
    if medium is None:
        return
    fmt = lambda place: "/".join(f"{r:.3f}" for r in medium[place]["ratio"])
    se = max(medium["origin"]["ratio_se"])
    print(f"  medium check (Mitsuba's half-space of the material against Chandrasekhar's exact reflectance, "
          f"θ_i {medium['theta_i_deg']:.0f}°, θ_o {medium['theta_o_deg']:.0f}°): at the origin {fmt('origin')} "
          f"± {se:.3f}: {'passes' if medium['pass'] else 'FAILS'} (within 3 SE + 0.5 %); "
          f"{medium['offset_cm']:.0f} cm off it {fmt('offset')} (Mitsuba 3.9 loses light within its ray epsilon, "
          f"which grows with the coordinates: what the references carry at most)")


def write_results(path, setup, comparison, calibration, rows, ranked, checks, per, budget, medium=None):
    """images.json: the comparison's numbers, rankings and checks."""
    cal, control = calibration.cal, calibration.control
    with open(path, "w") as f:
        json.dump({"scene": setup.name, "material": setup.material, "width": setup.width, "height": setup.height,
                   "spp": setup.spp, "reference_noise_rel": comparison.noise,
                   "silhouette_fraction": comparison.silhouette_fraction,
                   "calibration_rmse_rel": cal["rmse_noise_corrected"],
                   "calibration_rmse_se": cal["rmse_noise_corrected_se"],
                   "calibration_rmse_raw": cal["rmse_rel"],
                   "calibration_energy_ratio": cal["energy_ratio"],
                   "calibration_pass": calibration.passes,
                   "calibration_tolerance": {"rmse_rel": CAL_RMSE, "energy": CAL_ENERGY},
                   "negative_control": {"what": "--no-sss with the albedo × 0.8",
                                        "energy_ratio": control["energy_ratio"],
                                        "rmse_rel": control["rmse_noise_corrected"],
                                        "rejected": calibration.control_rejected},
                   "interreflection_ratio": calibration.interreflection,
                   "incidence_share_of_preint_mse": incidence_share(per),
                   "models": rows, "rankings": ranked, "checks": checks, "pass": all(checks.values()),
                   **({"medium_check": medium} if medium else {}),
                   **({"error_budget": budget} if budget else {})}, f, indent=2)


def main():
    """One comparison, as the module's docstring says: 0 where every check passes, else 1."""
    a = parser().parse_args()
    sss = sss_binary(a.sss)
    m = material(sss, a.material)
    setup = scenes.setup(a.scene, a.material, a.quick, a.models)
    out = os.path.join(a.out, scenes.folder(a.scene, a.material))
    os.makedirs(out, exist_ok=True)
    mi = mitsuba()
    refs, renders, rho, view = render_all(sss, mi, m, setup)
    comparison = compare_blocks(refs, renders)
    calibration = calibrate(refs, renders, comparison.sil)
    print_calibration(setup, comparison, calibration)
    # The medium's transport itself against exact theory, where the scene is index-matched.
    medium = halfspace.check(mi, m, MEDIUM_CHECK_OFFSET) if setup.scene.get("eta", 1.0) == 1.0 else None
    print_medium_check(medium)
    rows, per, per_spatial = score_models(comparison, renders.gather_noise)
    c = comparison
    budget = error_budget(c.o2s, renders.gather_noise, refs.alone, c.r2, c.d2, c.mask, rows,
                          len(setup.scene["media"]), calibration.interreflection)
    if a.arrays:
        write_arrays(os.path.join(out, "arrays.npz"), refs, renders, comparison, rho)
        write_view(out, view)
    if budget:
        print("\n".join(budget_lines(budget)))
    shown_k = shown_block_size(comparison.noise)
    panels = model_panels(out, comparison, renders.images, rows, shown_k)
    write_sheet(out, setup, comparison, calibration, refs, renders.lambertian, panels, shown_k)
    ranked, checks = rank(per, per_spatial, rows, calibration, setup.scene.get("kernel_order", True))
    if medium is not None:
        checks["the medium check passes"] = medium["pass"]
    ok = all(checks.values())
    write_results(os.path.join(out, "images.json"), setup, comparison, calibration, rows, ranked, checks, per,
                  budget, medium)
    for k, v in ranked.items():
        print(f"  {k}: {'yes' if v else 'undecided (within 3 SE)' if v is None else 'NO'}")
    for k, v in checks.items():
        if not v:
            print(f"  FAILED: {k}")
    print(f"images: {'agree' if ok else 'DISAGREE'} ({sum(checks.values())}/{len(checks)} checks) → {out}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

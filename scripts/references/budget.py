"""The error budget of one scene (issue 30): where the image error comes from, each term a
noise-corrected RMSE ± SE (a fraction of the mean of Mitsuba's reference without light between
surfaces), and its printed lines."""

import numpy as np

from references.scenes import GATHER_LABELS
from references.scoring import blocks, measure

# The error budget's terms (error_budget below, issue 30), as the tables name them.
BUDGET_TERMS = {
    "best_realtime": "best real-time ↔ reference",
    "radial": "radial MC gather ↔ reference",
    "directional": "directional MC gather ↔ reference (half-space limit)",
    "screen_space": "screen-space part: real-time (same tables) ↔ radial",
    "entry_direction": "entry direction: radial ↔ directional",
    "shifted_screen_space": "entry-shifted real-time ↔ directional",
    "shape_aware": "shape-aware MC gather ↔ reference",
    "shape": "shape: directional ↔ shape-aware gather",
    "between_surfaces": "light between surfaces: full ↔ reference",
}


def budget_lines(b, indent="    "):
    """The lines of an error budget: each term's noise-corrected RMSE ± SE, resolved or not."""
    lines = [f"{indent[:-2]}error budget against {b['reference']} (% of its mean; best real-time: "
             f"{b['best_realtime']}, {100 * b['best_realtime_full_reference']['rmse_noise_corrected']:.2f} ± "
             f"{100 * b['best_realtime_full_reference']['rmse_noise_corrected_se']:.2f} % from the full reference; "
             f"screen-space part with {b.get('screen_space_model', b['best_realtime'])}):"]
    for k, t in b["terms"].items():
        lines.append(f"{indent}{BUDGET_TERMS[k]:<52} {100 * t['rmse_noise_corrected']:6.2f} ± "
                     f"{100 * t['rmse_noise_corrected_se']:4.2f} % ({'resolved' if t['resolved'] else 'undecided'}), "
                     "energy " + "/".join(f"{e:.3f}" for e in t["energy_ratio"]))
    lines.append(f"{indent}self-interreflection of Lambertian surfaces (all bounces / direct − 1): "
                 + "/".join(f"{100 * e:.2f} %" for e in b["self_interreflection_lambert"]))
    return lines


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
    - shape_aware, shape (issue 47; where the run has the shape-aware gather): that gather
      against the reference, and directional ↔ shape-aware, what the body's curvature (mc in
      spheres and cavities) changes over the half-space;
    - between_surfaces: the full reference ↔ the one without light between surfaces (0 where the
      scene has one SSS shape on a black floor); self_interreflection_lambert: for a Lambertian
      surface of the same albedo, all bounces over direct light, − 1 (what light leaving a concave
      shape and entering it again is worth there; with several shapes it includes the light
      between them). None without both gathers (a run whose --models leaves them out)."""
    radial, directional, shape = GATHER_LABELS
    if not all(g in o2s for g in (radial, directional)):
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
            **({"shape_aware": term(img[shape], reference),
                "shape": term(img[directional], img[shape])} if shape in img else {}),
            "between_surfaces": between,
        },
        **({"shifted_model": shifted} if shifted else {}),
        "self_interreflection_lambert": [e - 1 for e in interreflection],
        "realtime_against_reference": against,
    }

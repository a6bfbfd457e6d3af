"""What must hold in one comparison, and what is reported: rankings of two models compared block
by block (scoring.paired: True, False, or None when undecided within 3 standard errors), the
energy checks, and the share of plain pre-integration's error that incidence-aware shading
removes."""

from references.scenes import GATHER_LABELS
from references.scoring import paired

# The entry-shifted real-time methods against the same without the shift.
SHIFT_PAIRS = [("preint-incidence-exit-entry-shift", "preint-incidence-exit-entry"),
               ("preint-incidence-translucency-exit-entry-shift", "preint-incidence-translucency-exit-entry")]
# Reported, not required: the best real-time methods against each other.
REPORTED_PAIRS = [("preint-incidence-exit", "preint-incidence"),
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
                  ("area-gather", "preint-translucency"), ("area-gather", "directional-dipole-mc")]


def rank(per, per_spatial, rows, calibration, kernel_order=True):
    """The rankings and checks of one comparison: `per` and `per_spatial` are each model's
    per-block estimates as it is and with each channel at its best factor (scoring.score_models),
    `rows` its rows (their energy ratios), `calibration` the scene's scoring.Calibration and
    `kernel_order` whether the kernels' order is required. A scene that fails calibration ranks
    nothing. Returns (rankings {name: True/False/None}, checks {name: passes})."""
    checks = {"calibration passes": calibration.passes,
              "negative control (albedo × 0.8) rejected": calibration.control_rejected}
    ranked = {}
    if not calibration.passes:
        return ranked, checks

    def closer(a, b):
        return paired(per[a], per[b])

    def pair(a, b):
        return a in per and b in per

    # The kernels' shapes: each closer than Lambertian shading, pre-integration and SVD rank-3
    # closer than SVD rank-1 (required where the scene says so, else reported).
    kernels = {f"{k} closer than lambert": closer(k, "lambert") for k in per if k != "lambert" and "-" not in k}
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
    if kernel_order:
        ranked.update(kernels)
    checks.update(energy_checks(rows, pair))
    # The entry shift (`--entry-shift`) is the directional gather's anisotropy in real time:
    # required to bring the real-time method closer where the exact half-space BSSRDF is
    # resolved closer than the radial profile (the bust's and the fins' grazing entry),
    # reported elsewhere (the sphere, where the half-space's forward transport overshoots
    # at the terminator, the directional gather farther than the radial one).
    radial, directional = GATHER_LABELS[:2]
    directional_helps = pair(directional, radial) and closer(directional, radial) is True
    if directional_helps:
        for a_, b_ in SHIFT_PAIRS:
            if pair(a_, b_):
                ranked[f"{a_} closer than {b_} (the directional gather closer than the radial)"] = closer(a_, b_)
    # A ranking fails only where it is resolved the wrong way round.
    checks.update({k: v is not False for k, v in ranked.items()})
    if not directional_helps:
        for a_, b_ in SHIFT_PAIRS:
            if pair(a_, b_):
                ranked[f"{a_} closer than {b_}"] = closer(a_, b_)
    # Reported, not required: the best real-time methods against each other.
    if not kernel_order:
        ranked.update(kernels)
    for a_, b_ in REPORTED_PAIRS:
        if pair(a_, b_):
            ranked[f"{a_} closer than {b_}"] = closer(a_, b_)
    return ranked, checks


def energy_checks(rows, pair):
    """The energy checks (required): the models' energy ratios per channel from `rows`, where
    pair(a, b) says both models were compared."""
    # Energy is a sum over thousands of pixels, far less noisy than the RMSE: with
    # incidence-aware shading every channel's energy ratio must lie within 2 % of 1 (issue
    # 15's goal) or at least closer to 1 than plain pre-integration's.
    e = {x["model"]: x["energy_ratio"] for x in rows}
    checks = {}
    if pair("preint-translucency", "preint"):
        # Light through the fins is light plain screen-space shading misses entirely.
        checks["translucency energy closer to Mitsuba than preint"] = all(
            abs(e["preint-translucency"][c] - 1) < abs(e["preint"][c] - 1) for c in range(3))
    if pair("preint-incidence", "preint"):
        checks["incidence-aware energy within 2 % of Mitsuba or closer than preint"] = all(
            abs(e["preint-incidence"][c] - 1) < max(0.02, abs(e["preint"][c] - 1)) for c in range(3))
    return checks


def incidence_share(per):
    """How much of plain pre-integration's error the angular dependence of total reflectance
    (incidence-aware shading) removes: the share of its noise-corrected MSE (None without both
    models, or where pre-integration's MSE is not above 0)."""
    if not ("preint-incidence" in per and "preint" in per):
        return None
    p_, i_ = per["preint"].mean(), per["preint-incidence"].mean()
    return float(1 - i_ / p_) if p_ > 0 else None

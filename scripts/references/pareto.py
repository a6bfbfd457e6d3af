#!/usr/bin/env python3
"""Run time against error for the real-time methods of one reference scene (issue 60): each
method's frame at 1920×1080 timed on this adapter by `sss render --bench frame` (the median of 5
frames on a renderer built once), three times interleaved with the separable default (`sss
render`'s own defaults), as a ratio to the default's frame in the same round (the median of the
three ratios), put against its noise-corrected error from images.py's images.json of the same
scene. Writes pareto.json and pareto.png (error ± SE against the cost ratio, each point
labelled, the front drawn) beside images.json.

Run images.py on the scene first (with the models to place), then e.g.
`python3 scripts/references/pareto.py --scene bust --sss target/ci/sss`. On lavapipe a bust
frame takes seconds: about 2 minutes per method."""

import argparse
import json
import os
import subprocess
import sys
import tempfile

if not __package__:
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from references import scenes  # noqa: E402
from references.ours import run, scene_args, sss_binary  # noqa: E402

# The real-time methods placed: the separable default and its variants, and the one-frame gathers.
SEPARABLE = ["preint-incidence-exit-entry-shift", "preint-incidence-exit-entry-shift-shape",
             "preint-incidence-translucency-exit-entry-shift",
             "preint-incidence-translucency-exit-entry-shift-shape"]
SHAPE_FLAGS = {"preint-incidence-exit-entry-shift-shape": ["--shape", "on"],
               "preint-incidence-translucency-exit-entry-shift-shape": ["--shape", "on"]}


def frame_ms(sss, args):
    """The median frame time [ms] `sss render ARGS --bench frame` reports."""
    with tempfile.TemporaryDirectory() as tmp:
        out = run([sss, "render", *args, "--bench", "frame", "--json", "--out", tmp])
    return json.loads(out)["frame_ms"]


def method_args(label, models, material, profiles, table_photons):
    """`sss render`'s arguments for a model label of the scene, as images.py renders it (the
    separable ones on `sss render`'s defaults, their shape flag kept)."""
    if label in SEPARABLE:
        return ["--material", material, "--profiles", profiles, *SHAPE_FLAGS.get(label, [])]
    extra = next(m[2] for m in models if m[0] == label)
    return [x.replace("{material}", material).replace("{profiles}", profiles)
            .replace("{table_photons}", str(table_photons)) for x in extra]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="sphere", choices=sorted(scenes.SCENES))
    ap.add_argument("--material", default="skin1")
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    ap.add_argument("--out", default="out/references", help="images.py's output folder")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds")
    a = ap.parse_args()
    sss = sss_binary(a.sss)
    folder = os.path.join(a.out, scenes.folder(a.scene, a.material))
    results = json.load(open(os.path.join(folder, "images.json")))
    rows = {m["model"]: m for m in results["models"]}
    setup = scenes.setup(a.scene, a.material, True)
    labels = [x for x in [*SEPARABLE, *scenes.FRAME_LABELS] if x in rows]
    if not labels:
        sys.exit(f"{folder}/images.json holds none of the real-time methods")
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        if any(shape[0] == "obj" for shape in setup.scene["media"]):
            files["bust"] = os.path.join(tmp, "bust.obj")
            scenes.bust_obj(files["bust"])
        common = scene_args(setup, files)
        common[common.index("--width") + 1], common[common.index("--height") + 1] = "1920", "1080"
        profiles = os.path.join(tmp, "profiles")
        default = [*common, "--material", a.material, "--profiles", profiles]
        ratios = {x: [] for x in labels}
        for r in range(a.rounds):
            for label in labels:
                base = frame_ms(sss, default)
                ms = frame_ms(sss, [*common, *method_args(label, scenes.SCENES[a.scene]["models"], a.material,
                                                          profiles, setup.table_photons)])
                ratios[label].append(ms / base)
                print(f"round {r + 1}: {label}: {ms:.0f} ms, default {base:.0f} ms, ratio {ms / base:.3f}",
                      flush=True)
    points = [{"model": x, "cost_ratio": sorted(ratios[x])[len(ratios[x]) // 2], "ratios": ratios[x],
               "error": rows[x]["rmse_noise_corrected"], "error_se": rows[x]["rmse_noise_corrected_se"]}
              for x in labels]
    front = [p["model"] for p in points
             if not any(q["cost_ratio"] <= p["cost_ratio"] and q["error"] < p["error"] for q in points)]
    json.dump({"scene": a.scene, "material": a.material, "size": [1920, 1080], "rounds": a.rounds,
               "points": points, "front": front}, open(os.path.join(folder, "pareto.json"), "w"), indent=2)
    plot(points, front, a, results, os.path.join(folder, "pareto.png"))
    for p in sorted(points, key=lambda p: p["cost_ratio"]):
        print(f"  {p['model']:<50} cost {p['cost_ratio']:.2f}× the default, error {100 * p['error']:.2f} ± "
              f"{100 * p['error_se']:.2f} %{'  (front)' if p['model'] in front else ''}")
    print(f"pareto → {os.path.join(folder, 'pareto.png')}")


def plot(points, front, a, results, path):
    """The sheet: error against cost ratio, each point labelled, the front joined."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 6))
    for p in points:
        on = p["model"] in front
        ax.errorbar(p["cost_ratio"], 100 * p["error"], yerr=100 * p["error_se"], fmt="o" if on else "x",
                    color="C0" if on else "0.5", capsize=3)
        ax.annotate(p["model"].replace("preint-incidence-", "preint+").replace("gather-frame-", "frame "),
                    (p["cost_ratio"], 100 * p["error"]), textcoords="offset points", xytext=(6, 4), fontsize=7)
    f = sorted((p for p in points if p["model"] in front), key=lambda p: p["cost_ratio"])
    ax.plot([p["cost_ratio"] for p in f], [100 * p["error"] for p in f], "-", color="C0", alpha=0.5)
    ax.axvline(2.0, color="C3", ls=":", lw=1)
    ax.set_xlabel("frame time at 1920×1080 / the separable default's (median of interleaved rounds)")
    ax.set_ylabel("noise-corrected RMSE against Mitsuba [% of the mean], ± SE")
    ax.set_title(f"Run time against error: {a.scene}, {a.material} (reference noise "
                 f"{100 * results['reference_noise_rel']:.1f} % per 2×2 block)")
    fig.text(0.01, 0.01, "Lower left is better; circles joined: the front; dotted: the 2× frame budget. "
                         "Errors with SE larger than the point's distance from another are not resolved.",
             fontsize=8)
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()

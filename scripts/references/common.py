"""Shared helpers of the Mitsuba 3 reference scripts: running `sss`, reading its outputs."""

import json
import os
import subprocess
import sys


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


# The error budget's terms (images.py's error_budget, issue 30), as the tables name them.
BUDGET_TERMS = {
    "best_realtime": "best real-time ↔ reference",
    "radial": "radial MC gather ↔ reference",
    "directional": "directional MC gather ↔ reference (half-space limit)",
    "screen_space": "screen-space part: real-time (same tables) ↔ radial",
    "entry_direction": "entry direction: radial ↔ directional",
    "shifted_screen_space": "entry-shifted real-time ↔ directional",
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

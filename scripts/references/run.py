#!/usr/bin/env python3
"""Regenerates every Mitsuba 3 reference and prints the comparison tables: Rd(r) profiles
(profiles.py) and images of the sphere scene and of the fin scene (images.py). --quick is the CI
size (a few minutes on 2 cores); without it, the full version (larger images, much longer).
Exits non-zero when an agreement test fails. Outputs: OUT/profiles.json, OUT/images/,
OUT/images-fin/."""

import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    ap.add_argument("--out", default="out/references")
    a = ap.parse_args()
    extra = (["--quick"] if a.quick else []) + (["--sss", a.sss] if a.sss else []) + ["--out", a.out]
    failed = []
    for script, args in [("profiles.py", []), ("images.py", []), ("images.py", ["--scene", "fin"])]:
        name = " ".join([script, *args])
        print(f"== {name}", flush=True)
        if subprocess.run([sys.executable, os.path.join(HERE, script), *args, *extra]).returncode != 0:
            failed.append(name)
    print("references: " + ("all agree" if not failed else "FAILED " + ", ".join(failed)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

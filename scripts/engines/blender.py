#!/usr/bin/env python3
"""Blender's own renderers with the parameters `sss engine-params --engine blender` writes, against
the path-traced truth: Cycles' random walk (the material's σa, σs, g through Cycles' remap),
Cycles' Christensen–Burley (the Burley profile fitted to the Monte Carlo profile) and EEVEE, the
real-time peer (the same Burley parameters), through `bpy` (Blender as a Python module, CPU only;
EEVEE through Mesa's software OpenGL).

  slab   A thick flat slab of the material (20 × 20 × 10 cm) under a distant light, seen from
         above through an orthographic camera: what CI runs (about 15 s). Cycles' walk starts on
         the camera's side (refracting the view ray, by at least its clamped IOR 1.01) and reaches
         the light through a diffuse BSDF where it leaves (subsurface_bounce,
         subsurface_shader_data_setup in the Cycles source bpy ships). So under normal light,
         index-matched, π × radiance / irradiance seen from θ is the escape probability of a walk
         entering at the refracted θt: `sss simulate`'s total diffuse reflectance Rd(θt) of the
         same σa, σs, g. Required within 3 % per channel at 0° and four Gauss–Legendre view
         angles: the test of the parameters. Reported: what Cycles leaves out (the light's
         direction: the same image under a 60° light; so its reflected energy under normal light
         is the white-sky albedo Σ w·Rd(θ), not Rd(0°); at the material's own η, no Fresnel or
         internal reflection where the walk leaves), and Christensen–Burley's ratio. Opaque white
         Lambertian slabs calibrate the light: π × radiance / irradiance must be 1 within 0.5 %.
  scene  The scenes of scripts/references/images.py (camera, light, geometry, black floor), built
         in Blender and rendered with each renderer, scored against the Mitsuba reference that
         `images.py --arrays` left in OUT/<scene folder>/arrays.npz, with the same code
         (references.scoring's score, measure, calibrated): calibration first (Blender's opaque
         Lambertian surfaces, direct light only, against Mitsuba's; a renderer that fails is
         reported as uncalibrated and ranks nothing, and a failing Cycles calibration fails the
         run), noise-corrected RMSE ± SE (each Blender render is two half-budget seeds, its own
         noise corrected for as the reference's is), energy ratios, paired rankings against our
         best real-time method in that file (resolved at 3 SE, else undecided), and one labelled
         sheet (blender-sheet.png). The rows are added to images.json's models (as
         blender-cycles-random-walk, blender-cycles-burley, blender-eevee), so
         `sss reproduce --references` shows them beside ours. The random walk's error is traced:
         its image times Rd(θ)/A (our incidence-aware over plain render, times Rd(0°) over the
         white-sky albedo A, from `sss simulate --incidence-angles`) undoes its blindness to the
         light's direction; what remains is reported beside it.

Units: Blender units are centimetres here (the scenes' unit), so the Subsurface Scale that
engine-params gives in metres is × 100. Lights: a Mitsuba point light of intensity I [W/sr] is a
Blender point light of power 4π·I [W] (isotropic: Cycles' watts are radiant flux here), and a
directional light of irradiance E a sun of strength E; the calibrations check both.
"""

import argparse
import contextlib
import json
import math
import os
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass

import numpy as np

# Blender 5.0 warns that `use_nodes` goes away in 6.0; until then it is how node materials start.
warnings.filterwarnings("ignore", message=".*use_nodes.*", category=DeprecationWarning)
HERE = os.path.dirname(os.path.abspath(__file__))
# Run by path (`python3 scripts/engines/blender.py`, as tests/blender.rs and run.py do): Python
# puts this folder on sys.path; the scripts' root, which holds the `references` package, goes first.
sys.path.insert(0, os.path.dirname(HERE))

from references import scenes, scoring, sheets  # noqa: E402
from references.ours import material, material_toml, run, sss_binary  # noqa: E402

# The renderers compared, as images.json's model labels.
CYCLES_RW, CYCLES_BURLEY, EEVEE = "blender-cycles-random-walk", "blender-cycles-burley", "blender-eevee"
# The thin slab [cm]: 1.5–3 mean free paths of Skin1, where reflectance depends on lengths.
THIN_SLAB = 0.2
# EEVEE's samples at most: its frames are smooth (temporal anti-aliasing, shadow and
# scattering jitter), 128 of them leave little noise for the correction, and 512 at 384×216
# take 6 minutes on Mesa's software OpenGL (Cycles' random walk at 1024 spp: 2.4 minutes).
EEVEE_SAMPLES = 128
# Cycles' smallest subsurface IOR (it clamps to [1.01, 3.8] in bssrdf_setup).
CYCLES_MIN_IOR = 1.01
# The slab check: the random walk's reflected energy within 3 % of `mc`'s total reflectance; the
# white calibration slab's radiance within 0.5 % of E/π.
SLAB_TOLERANCE, SLAB_CALIBRATION = 0.03, 0.005
# `slab --g`: Cycles' reflectance at normal incidence within 1 % of the exact medium's Rd(0°).
SWEEP_TOLERANCE = 0.01


def blender():
    """bpy, or a clear exit."""
    try:
        import bpy
    except ImportError:
        sys.exit("Blender's Python module is not installed: pip install -r scripts/engines/requirements.txt "
                 "(bpy 5.0.1, CPython 3.11)")
    return bpy


def engine_params(sss, material_file):
    """`sss engine-params FILE --engine blender --json`: the Christensen–Burley fields and the
    random walk's, each as {field name: value}."""
    j = json.loads(run([sss, "engine-params", material_file, "--engine", "blender", "--json"]))
    fields = lambda p: {f["name"]: f["value"] for f in p["fields"]}
    return fields(j["params"]), fields(j["random_walk"])


@contextlib.contextmanager
def quiet():
    """Blender's own log (a line per rendered tile and sample, EGL's complaints) goes to a file
    instead of the terminal; its tail is shown if the render fails."""
    sys.stdout.flush()
    sys.stderr.flush()
    with tempfile.TemporaryFile() as log:
        saved = os.dup(1), os.dup(2)
        os.dup2(log.fileno(), 1)
        os.dup2(log.fileno(), 2)
        try:
            yield
        except BaseException:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            log.seek(0)
            sys.stderr.write(log.read().decode(errors="replace")[-4000:])
            raise
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


class Scene:
    """A Blender scene in centimetres, built from nothing: objects, materials, one light, a
    camera, and the render settings that make Blender's image comparable with Mitsuba's (linear
    radiance, a one-pixel box filter, no denoising, clamping, adaptive sampling or light
    threshold, a black world)."""

    def __init__(self, width, height):
        self.bpy = bpy = blender()
        bpy.ops.wm.read_factory_settings(use_empty=True)
        s = self.scene = bpy.context.scene
        s.render.resolution_x, s.render.resolution_y = width, height
        s.render.resolution_percentage = 100
        s.render.image_settings.file_format = "OPEN_EXR"
        s.render.image_settings.color_depth = "32"
        s.render.image_settings.exr_codec = "ZIP"
        s.view_settings.view_transform = "Standard"
        s.view_settings.look = "None"
        s.view_settings.exposure = 0.0
        s.view_settings.gamma = 1.0
        world = bpy.data.worlds.new("black")
        world.use_nodes = True
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
        s.world = world
        s.render.filter_size = 1.0

    def material(self, name, build):
        """A node material: build(nodes) returns the shader node whose BSDF is the surface."""
        mat = self.bpy.data.materials.new(name)
        mat.use_nodes = True
        nodes = mat.node_tree.nodes
        nodes.clear()
        out = nodes.new("ShaderNodeOutputMaterial")
        mat.node_tree.links.new(build(nodes).outputs[0], out.inputs["Surface"])
        return mat

    def diffuse(self, rho):
        """An opaque Lambertian surface of reflectance rho [R, G, B]."""
        def build(nodes):
            n = nodes.new("ShaderNodeBsdfDiffuse")
            n.inputs["Color"].default_value = (*rho, 1.0)
            n.inputs["Roughness"].default_value = 0.0
            return n
        return self.material(f"diffuse {rho}", build)

    def principled(self, fields, method, ior):
        """A Principled BSDF from engine-params' fields (Subsurface Scale in metres → cm), with
        Subsurface Method `method` (RANDOM_WALK or BURLEY), smooth, of index `ior`."""
        def build(nodes):
            n = nodes.new("ShaderNodeBsdfPrincipled")
            n.subsurface_method = method
            for name, v in fields.items():
                if name == "Subsurface Scale":
                    v = 100.0 * v
                if name in ("IOR", "Roughness"):
                    continue
                n.inputs[name].default_value = (*v, 1.0) if name == "Base Color" else v
            n.inputs["IOR"].default_value = ior
            n.inputs["Roughness"].default_value = 0.0
            return n
        return self.material(f"principled {method}", build)

    def link(self, obj, mat):
        obj.data.materials.clear()
        obj.data.materials.append(mat)
        return obj

    def sphere(self, centre, radius, mat):
        self.bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=6, radius=radius, location=centre)
        obj = self.bpy.context.active_object
        self.bpy.ops.object.shade_smooth()
        return self.link(obj, mat)

    def box(self, lo, hi, mat):
        self.bpy.ops.mesh.primitive_cube_add(size=2.0, location=[(lo[i] + hi[i]) / 2 for i in range(3)],
                                             scale=[(hi[i] - lo[i]) / 2 for i in range(3)])
        self.bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
        return self.link(self.bpy.context.active_object, mat)

    def obj(self, path, mat):
        """A mesh from an OBJ file, in the file's own coordinates, with its vertex normals."""
        self.bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
        obj = self.bpy.context.selected_objects[0]
        # The importer turns the file's y-up into Blender's z-up (a +90° turn about x): undo it.
        obj.rotation_euler = (0.0, 0.0, 0.0)
        self.bpy.ops.object.shade_smooth()
        return self.link(obj, mat)

    def floor(self, mat, size=120.0):
        """A square of side `size` [cm] in the plane y = 0, facing +y (Mitsuba's floor)."""
        self.bpy.ops.mesh.primitive_plane_add(size=size, rotation=(-math.pi / 2, 0.0, 0.0))
        return self.link(self.bpy.context.active_object, mat)

    def point_light(self, position, intensity):
        """A point light of radiant intensity `intensity` [W/sr]: radius 0, no soft falloff."""
        light = self.bpy.data.lights.new("point", type="POINT")
        light.energy = 4.0 * math.pi * intensity
        light.shadow_soft_size = 0.0
        light.use_soft_falloff = False
        light.shadow_filter_radius = 0.0   # EEVEE: hard shadow-map edges, as the light is a point
        return self.place(self.bpy.data.objects.new("point", light), position, None)

    def sun(self, towards, irradiance):
        """A distant light of irradiance `irradiance` [W/m² in Blender's words] from direction
        `towards` (pointing at the light)."""
        light = self.bpy.data.lights.new("sun", type="SUN")
        light.energy = irradiance
        light.angle = 0.0
        light.shadow_filter_radius = 0.0
        return self.place(self.bpy.data.objects.new("sun", light), (0.0, 0.0, 0.0), [-x for x in towards])

    def camera(self, eye, target, fov_y=None, ortho=None):
        """A perspective camera of vertical field of view fov_y [deg], or an orthographic one
        `ortho` [cm] wide, at `eye` looking at `target` with +y up."""
        cam = self.bpy.data.cameras.new("camera")
        if ortho:
            cam.type, cam.ortho_scale = "ORTHO", ortho
        else:
            cam.sensor_fit, cam.angle_y = "VERTICAL", math.radians(fov_y)
        cam.clip_start, cam.clip_end = 0.01, 1000.0
        forward = [t - e for t, e in zip(target, eye)]
        obj = self.place(self.bpy.data.objects.new("camera", cam), eye, forward)
        self.scene.camera = obj
        return obj

    def place(self, obj, position, forward):
        """Links `obj` at `position`, its −z axis along `forward` (if any) with +y up, as
        Blender's cameras and lights look."""
        from mathutils import Matrix, Vector
        self.scene.collection.objects.link(obj)
        m = Matrix.Translation(Vector(position))
        if forward is not None:
            f = Vector(forward).normalized()
            up = Vector((0.0, 1.0, 0.0)) if abs(f.y) < 0.999 else Vector((0.0, 0.0, -1.0))
            r = f.cross(up).normalized()
            m = m @ Matrix((r, r.cross(f), -f)).transposed().to_4x4()
        obj.matrix_world = m
        return obj

    def render(self, engine, spp, seed, direct_only=False):
        """A linear RGB image [height × width × 3], top row first."""
        bpy, s = self.bpy, self.scene
        s.render.engine = engine
        if engine == "CYCLES":
            c = s.cycles
            c.device, c.samples, c.seed = "CPU", spp, seed
            c.use_adaptive_sampling = c.use_denoising = c.use_light_tree = False
            c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
            c.light_sampling_threshold = 0.0
            c.blur_glossy = 0.0
            c.pixel_filter_type = "BOX"
            c.filter_width = 1.0
            c.use_auto_tile = False
            bounces = 0 if direct_only else 64
            c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = bounces
            c.transparent_max_bounces = 8
        else:
            e = s.eevee
            e.taa_render_samples = spp
            e.light_threshold = 1e-6
            e.use_shadows = True
        with tempfile.TemporaryDirectory() as tmp:
            s.render.filepath = os.path.join(tmp, "render.exr")
            with quiet():
                bpy.ops.render.render(write_still=True)
            img = bpy.data.images.load(s.render.filepath)
            px = np.empty(len(img.pixels), dtype=np.float32)
            img.pixels.foreach_get(px)
            h, w = s.render.resolution_y, s.render.resolution_x
            bpy.data.images.remove(img)
        return np.flipud(px.reshape(h, w, 4)[:, :, :3]).astype(np.float64)


def build(width, height, scene, surface, files):
    """One of images.py's scenes (its SCENES entry) in Blender, every SSS shape of material
    `surface`, occluders and the floor black."""
    s = Scene(width, height)
    black = s.diffuse([0.0, 0.0, 0.0])
    for shape in scene["media"]:
        if shape[0] == "sphere":
            s.sphere(shape[1], shape[2], surface(s))
        elif shape[0] == "obj":
            s.obj(files[shape[1]], surface(s))
        else:
            s.box(shape[1], shape[2], surface(s))
    for lo, hi in scene["boxes"]:
        s.box(lo, hi, black)
    s.floor(black)
    kind, v, *rest = scene["light"]
    if kind == "point":
        s.point_light(v, rest[0])
    elif kind == "dir":
        s.sun(v, rest[0])
    else:
        sys.exit(f"the {kind} light is not built in Blender (scenes with point and directional lights only)")
    eye, target, fov = scene["camera"]
    s.camera(eye, target, fov)
    return s


def halves(s, engine, spp, seed):
    """Two renders at half the samples each with independent seeds: (mean, their difference on
    2×2 blocks, seconds)."""
    t = time.time()
    a, b = s.render(engine, spp // 2, seed), s.render(engine, spp // 2, seed + 1)
    return 0.5 * (a + b), scoring.blocks(a) - scoring.blocks(b), time.time() - t


# Blender's engines as the sheet names them.
ENGINE_NAMES = {"CYCLES": "Cycles", "BLENDER_EEVEE": "EEVEE"}
# Each renderer's label: its Blender engine, Subsurface Method and engine-params' field set.
RENDERERS = {CYCLES_RW: ("CYCLES", "RANDOM_WALK", "random_walk"),
             CYCLES_BURLEY: ("CYCLES", "BURLEY", "burley"),
             EEVEE: ("BLENDER_EEVEE", "BURLEY", "burley")}


@dataclass
class Reference:
    """The Mitsuba reference `images.py --arrays` left for one scene (arrays.npz), on the 2×2
    blocks images.py scores on: linear radiance, [h × w × 3] images and [h/2 × w/2 × 3] blocks."""
    arr: object            # arrays.npz as loaded (our models' images among them)
    ref: np.ndarray        # the reference image
    r2: np.ndarray         # the reference on 2×2 blocks
    d2: np.ndarray         # the difference of its two halves on 2×2 blocks (its noise)
    mask: np.ndarray       # the blocks compared [h/2 × w/2], bool
    mean: float            # the reference's mean over the compared blocks
    sil: np.ndarray        # blocks with a silhouette or crease pixel [h/2 × w/2], bool
    cal_ref: np.ndarray    # Mitsuba's calibration: opaque Lambertian surfaces, direct light only
    c2: np.ndarray         # the calibration on 2×2 blocks
    dc2: np.ndarray        # the difference of its two halves on 2×2 blocks


def load_reference(a):
    """The scene (its SCENES entry), output folder, images.json's path, arrays.npz and
    images.json of `scene`'s arguments; exits where images.py --arrays has not left them."""
    sc = scenes.SCENES[a.scene]
    if sc["light"][0] == "area":
        sys.exit(f"--scene {a.scene}: its area light is not built in Blender; use sphere, fin or bust")
    out = os.path.join(a.out, scenes.folder(a.scene, a.material))
    arrays, summary = os.path.join(out, "arrays.npz"), os.path.join(out, "images.json")
    if not (os.path.exists(arrays) and os.path.exists(summary)):
        sys.exit(f"{arrays} or {summary} is missing: run scripts/references/images.py --scene {a.scene} "
                 f"--material {a.material} --arrays --out {a.out} first")
    arr, info = np.load(arrays), json.load(open(summary))
    if "calibration_a" not in arr:
        sys.exit(f"{arrays} predates the calibration arrays: rerun images.py --arrays")
    return sc, out, summary, arr, info


def reference_blocks(arr):
    """The Reference of arrays.npz `arr`, on images.py's blocks and mask."""
    blocks = scoring.blocks
    ref = arr["reference"]
    r2, d2, mask = blocks(ref), blocks(arr["reference_a"]) - blocks(arr["reference_b"]), arr["mask_blocks"]
    mean = r2[mask].mean()
    sil = blocks(arr["silhouettes"][:, :, None].astype(np.float64))[:, :, 0] > 0
    cal_ref = 0.5 * (arr["calibration_a"] + arr["calibration_b"])
    c2, dc2 = blocks(cal_ref), blocks(arr["calibration_a"]) - blocks(arr["calibration_b"])
    return Reference(arr, ref, r2, d2, mask, mean, sil, cal_ref, c2, dc2)


def render_scene(sss, a, sc, arr, spp, labels):
    """Every Blender render of one scene: each engine's calibration (opaque Lambertian surfaces of
    images.py's albedo ρ, direct light only) and each renderer of `labels` (two half-budget
    seeds of `spp` samples, EEVEE at most EEVEE_SAMPLES). Returns (renders {label: (image, its
    noise on 2×2 blocks, seconds, spp)}, calibrations {engine: (image, its noise on 2×2
    blocks)}, seconds {what: s}, the medium's white-sky albedo and Rd(0°), engine-params'
    fields)."""
    h, w = arr["reference"].shape[:2]
    rho = [float(x) for x in arr["rho"]]
    eta = sc.get("eta", 1.0)
    m = material(sss, a.material)
    renders, calibrations, seconds = {}, {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        toml = material_toml(m, eta, os.path.join(tmp, "medium.toml"))
        burley, walk = engine_params(sss, toml)
        # The medium's white-sky albedo A = Σ w·Rd(θ) and Rd(0°), for the attribution below.
        angles, weights = gauss_angles(4)
        rd = [x[0] for x in incidence_rd(sss, toml, [0.0, *angles], 300_000, tmp)]
        white_sky = {"rd0": rd[0], "albedo": [sum(w * r[c] for w, r in zip(weights, rd[1:])) for c in range(3)]}
        params = {"burley": burley, "random_walk": walk}
        files = {}
        if any(shape[0] == "obj" for shape in sc["media"]):
            files["bust"] = os.path.join(tmp, "bust.obj")
            scenes.bust_obj(files["bust"])
        for label in labels:
            engine, method, which = RENDERERS[label]
            # Calibration: the same scene with opaque Lambertian surfaces of reflectance ρ, direct
            # light only (Cycles: no bounces; EEVEE has no indirect light without baked probes).
            if engine not in calibrations:
                s = build(w, h, sc, lambda s: s.diffuse(rho), files)
                t = time.time()
                a_, b_ = (s.render(engine, max(spp // 8, 8), seed, direct_only=True) for seed in (11, 12))
                calibrations[engine] = (0.5 * (a_ + b_), scoring.blocks(a_) - scoring.blocks(b_))
                seconds[f"{engine} calibration"] = time.time() - t
            s = build(w, h, sc, lambda s: s.principled(params[which], method, eta), files)
            n = min(spp, EEVEE_SAMPLES) if engine == "BLENDER_EEVEE" else spp
            renders[label] = (*halves(s, engine, n, 1), n)
            seconds[label] = renders[label][2]
            print(f"  {label}: {n} spp in {seconds[label]:.0f} s", flush=True)
    return renders, calibrations, seconds, white_sky, params


def score_calibrations(r, calibrations):
    """Each engine's calibration against Mitsuba's direct light on Reference `r`, with its
    negative control (albedo × 0.8), printed: {engine: measure()'s numbers, with "pass" and
    "negative_control_rejected"}."""
    cal_rows = {}
    for engine, (img, noise2) in calibrations.items():
        l2 = scoring.blocks(img)
        cal_mask = ((r.c2.sum(2) > 0) | (l2.sum(2) > 0)) & ~r.sil
        cal_mean = r.c2[cal_mask].mean()
        _, cal = scoring.measure(l2, r.c2, r.dc2, cal_mask, cal_mean, noise2)
        _, control = scoring.measure(0.8 * l2, r.c2, r.dc2, cal_mask, cal_mean, 0.8 * noise2)
        cal["pass"], cal["negative_control_rejected"] = scoring.calibrated(cal), not scoring.calibrated(control)
        cal_rows[engine] = cal
        e = cal["energy_ratio"]
        print(f"  calibration, {engine} (Lambertian ρ, direct light) against Mitsuba's: noise-corrected RMSE "
              f"{100 * cal['rmse_noise_corrected']:.2f} ± {100 * cal['rmse_noise_corrected_se']:.2f} %, energy "
              f"{e[0]:.4f}/{e[1]:.4f}/{e[2]:.4f}: {'passes' if cal['pass'] else 'FAILS: ranks nothing'}; "
              f"albedo × 0.8 {'rejected' if cal['negative_control_rejected'] else 'NOT REJECTED'}")
    return cal_rows


def our_scores(r):
    """Our real-time methods in arrays.npz (Monte Carlo gathers and plain Lambertian shading left
    out), each score()d on Reference `r`: ({label: (per-block estimates, row)}, the best label by
    noise-corrected error, or None)."""
    ours = {k[len("model_"):]: scoring.score(scoring.blocks(r.arr[k]), r.r2, r.d2, r.mask, r.mean)
            for k in r.arr.files if k.startswith("model_") and k != "model_lambert" and "surface-gather" not in k}
    best = min(ours, key=lambda k: ours[k][1]["rmse_noise_corrected"]) if ours else None
    return ours, best


def score_renders(r, renders, cal_rows, seconds, ours, best, version):
    """Each Blender render's row on Reference `r`, its sheet panels, and its ranking against our
    best real-time method: (rows of calibrated renderers, rows of uncalibrated ones, per-block
    estimates {label: ...} of calibrated ones, panels, rankings). `version`: Blender's."""
    rows, uncalibrated, per, panels, ranked = [], [], {}, [], {}
    for label, (img, noise2, _, n) in renders.items():
        engine = RENDERERS[label][0]
        calibrated = cal_rows[engine]["pass"] and cal_rows[engine]["negative_control_rejected"]
        p_, row = scoring.score(scoring.blocks(img), r.r2, r.d2, r.mask, r.mean, noise2)
        row.update({"renderer": f"Blender {version} {engine}, Subsurface Method {RENDERERS[label][1]}",
                    "spp": n, "seconds": seconds[label]})
        shown = sheets.tonemap(img, 1.0 / r.mean / 4)
        note = "" if calibrated else " (uncalibrated)"
        panels += [(f"{label}{note}: {100 * row['rmse_noise_corrected']:.1f} ± "
                    f"{100 * row['rmse_noise_corrected_se']:.1f} %", shown, "rgb"),
                   (f"{label} − Mitsuba", (img - r.ref).mean(2) / r.mean, "diff")]
        # A renderer whose calibration fails is reported, never ranked nor listed with ours.
        if not calibrated:
            uncalibrated.append({"model": label, **row})
            continue
        per[label] = p_
        rows.append({"model": label, **row})
        if best:
            ranked[f"{label} closer than {best}"] = scoring.paired(per[label], ours[best][0])
    return rows, uncalibrated, per, panels, ranked


def random_walk_attribution(r, renders, per, ours, white_sky):
    """How much of Cycles' random walk's error its blindness to the light's direction explains:
    its row with its image times Rd(θ)/A, or None (without the random walk calibrated, or
    without a plain and incidence-aware pair of our models)."""
    # Cycles' walk starts at the camera's side and reaches the light through a diffuse BSDF: the
    # light's direction does not enter (the slab check), so at every incidence it reflects the
    # white-sky albedo A where the medium reflects Rd(θ). Our renders with and without
    # incidence-aware shading differ per pixel by exactly Rd(θ)/Rd(0°): Cycles' image times
    # Rd(θ)/A shows how much of its error that explains.
    pair = next(((k, k.replace("preint", "preint-incidence", 1)) for k in ours
                 if k.startswith("preint") and "incidence" not in k
                 and k.replace("preint", "preint-incidence", 1) in ours), None)
    if not (CYCLES_RW in per and pair):
        return None
    plain, aware = r.arr[f"model_{pair[0]}"], r.arr[f"model_{pair[1]}"]
    factor = np.where(plain > 0, aware / np.where(plain > 0, plain, 1.0), 1.0) * (
        np.array(white_sky["rd0"]) / np.array(white_sky["albedo"]))
    img, noise2, _, _ = renders[CYCLES_RW]
    _, row = scoring.score(scoring.blocks(img * factor), r.r2, r.d2, r.mask, r.mean, noise2 * scoring.blocks(factor))
    return {"factor_from": [pair[1], pair[0]], **white_sky, **row}


def write_blender_sheet(path, a, r, ours, best, calibrations, panels, w, h, version):
    """blender-sheet.png: the reference, our best real-time method, each engine's calibration
    against Mitsuba's direct light, then Blender's `panels`."""
    head = [("Mitsuba (path-traced reference)", sheets.tonemap(r.ref, 1.0 / r.mean / 4), "rgb")]
    if best:
        img = r.arr[f"model_{best}"]
        row = ours[best][1]
        head += [(f"ours, best real-time: {100 * row['rmse_noise_corrected']:.1f} ± "
                  f"{100 * row['rmse_noise_corrected_se']:.1f} %\n({best})", sheets.tonemap(img, 1.0 / r.mean / 4),
                  "rgb"),
                 ("ours − Mitsuba", (img - r.ref).mean(2) / r.mean, "diff")]
    cal_ref = r.cal_ref
    for engine, (img, _) in calibrations.items():
        head.append((f"{ENGINE_NAMES[engine]}, Lambertian (calibration) − Mitsuba",
                     (img - cal_ref).mean(2) / cal_ref[cal_ref.sum(2) > 0].mean(), "diff"))
    sheets.sheet(path,
                 f"{a.scene} / {a.material}, {w}×{h}: Blender {version} with `sss engine-params` against "
                 f"Mitsuba\nnoise-corrected RMSE ± SE (% of the reference's mean)", head + panels, 0.2,
                 "each render − Mitsuba (Blender's, ours, or a calibration − Mitsuba's direct light)")


def print_scores(ours, best, rows, uncalibrated, attribution, ranked):
    """Our best real-time method's row, Blender's rows (the uncalibrated and the random walk's
    attribution marked as such), and the rankings."""
    print(f"  {'model':<40} {'error (noise-corrected)':>16} {'spatial':>8} {'SSIM':>7}  energy R/G/B")
    extra = [{**r, "model": r["model"] + " (uncalibrated)"} for r in uncalibrated]
    if attribution:
        extra.append({**attribution, "model": f"{CYCLES_RW} × Rd(θ)/A"})
    for r in ([{"model": best, **ours[best][1]}] if best else []) + rows + extra:
        e = r["energy_ratio"]
        print(f"  {r['model']:<40} {100 * r['rmse_noise_corrected']:>6.2f} ± {100 * r['rmse_noise_corrected_se']:4.2f} %"
              f" {100 * r['rmse_spatial']:>6.2f} % {r['ssim']:>7.4f}  {e[0]:.3f}/{e[1]:.3f}/{e[2]:.3f}")
    for k, v in ranked.items():
        print(f"  {k}: {'yes' if v else 'undecided (within 3 SE)' if v is None else 'no'}")


def scene_command(a):
    """`blender.py scene`: Blender's renderers on one of images.py's scenes, scored against its
    Mitsuba reference; their rows join images.json. 0 where Cycles is calibrated."""
    sss = sss_binary(a.sss)
    sc, out, summary, arr, info = load_reference(a)
    labels = [x for x in a.renderers.split(",") if x]
    unknown = set(labels) - set(RENDERERS)
    if unknown:
        sys.exit(f"--renderers: {', '.join(sorted(unknown))} unknown (choose from {', '.join(RENDERERS)})")
    bpy = blender()
    h, w = arr["reference"].shape[:2]
    spp = a.spp or info["spp"]
    renders, calibrations, seconds, white_sky, params = render_scene(sss, a, sc, arr, spp, labels)
    # Scoring, with images.py's code on its blocks and mask.
    r = reference_blocks(arr)
    cal_rows = score_calibrations(r, calibrations)
    ours, best = our_scores(r)
    version = bpy.app.version_string
    rows, uncalibrated, per, panels, ranked = score_renders(r, renders, cal_rows, seconds, ours, best, version)
    attribution = random_walk_attribution(r, renders, per, ours, white_sky)
    if CYCLES_RW in per and CYCLES_BURLEY in per:
        ranked[f"{CYCLES_RW} closer than {CYCLES_BURLEY}"] = scoring.paired(per[CYCLES_RW], per[CYCLES_BURLEY])
    if EEVEE in per and CYCLES_BURLEY in per:
        ranked[f"{EEVEE} closer than {CYCLES_BURLEY}"] = scoring.paired(per[EEVEE], per[CYCLES_BURLEY])
    write_blender_sheet(os.path.join(out, "blender-sheet.png"), a, r, ours, best, calibrations, panels, w, h, version)
    info["models"] = [row for row in info["models"] if not row["model"].startswith("blender-")] + rows
    info["rankings"] = {k: v for k, v in info.get("rankings", {}).items() if not k.startswith("blender-")}
    info["rankings"].update(ranked)
    info["blender"] = {"version": version, "spp": spp, "best_ours": best,
                       "calibration": cal_rows, "uncalibrated": uncalibrated,
                       "random_walk_incidence_corrected": attribution, "seconds": seconds, "params": params}
    with open(summary, "w") as f:
        json.dump(info, f, indent=2)
    print_scores(ours, best, rows, uncalibrated, attribution, ranked)
    # Cycles' calibration is the instrument's: where it fails, nothing here is trusted. EEVEE's is
    # a finding about EEVEE (its shadow maps), reported above.
    cycles = cal_rows.get("CYCLES")
    ok = cycles is None or (cycles["pass"] and cycles["negative_control_rejected"])
    print(f"blender: {'Cycles calibrated' if ok else 'CYCLES CALIBRATION FAILED'} → {out}")
    return 0 if ok else 1


def gauss_angles(n):
    """Polar angles [deg] and weights of n-point Gauss–Legendre quadrature in u = cos²θ on [0, 1]:
    the white-sky albedo 2∫₀¹ R(μ)·μ dμ = ∫₀¹ R(√u) du ≈ Σ w_k·R(θ_k)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return [float(math.degrees(math.acos(math.sqrt((1 + t) / 2)))) for t in x], [float(v / 2) for v in w]


def incidence_rd(sss, toml, angles, photons, tmp):
    """`sss simulate --incidence-angles`: the total diffuse reflectance Rd(θ) of the material file
    `toml` for a beam at each of `angles` [deg], per channel with its standard error, as
    [(rd R/G/B, se R/G/B)]."""
    run([sss, "simulate", toml, "--photons", "1000", "--profile-only", "--out", tmp, "--incidence-angles",
         ",".join(f"{x:.6f}" for x in angles), "--incidence-photons", str(photons)])
    stem = os.path.basename(toml)[: -len(".toml")]
    table = json.load(open(os.path.join(tmp, f"{stem}.summary.json")))["incidence"]
    return [([t["rd"][c] for c in "RGB"], [t["rd_se"][c] for c in "RGB"]) for t in table]


def slab_command(a):
    sss = sss_binary(a.sss)
    m = material(sss, a.material)
    own_eta = float(m.get("eta", 1.0))
    bpy = blender()
    res, spp = a.resolution, a.spp
    angles, weights = gauss_angles(4)
    views = [0.0, *angles]
    # Cycles clamps the subsurface IOR to [1.01, 3.8] (bssrdf_setup): even index-matched, the view
    # ray is refracted by 1.01 on its way in, so the walk that answers a view at θ enters at θt.
    refracted = [math.degrees(math.asin(math.sin(math.radians(v)) / CYCLES_MIN_IOR)) for v in views]

    def render(surface, light_deg=0.0, view_deg=0.0, thickness=10.0, direct_only=False):
        """π × radiance over the irradiance of a sun of strength 1 (on a plane facing it) at
        `light_deg`, seen from `view_deg` (both polar, on opposite sides of the normal), per
        channel, with its standard error from the pixels' spread: for a Lambertian reflector,
        its reflectance."""
        s = Scene(res, res)
        s.box((-10.0, -thickness, -10.0), (10.0, 0.0, 10.0), surface(s))
        ti, to = math.radians(light_deg), math.radians(view_deg)
        s.sun((math.sin(ti), math.cos(ti), 0.0), 1.0)
        # The central 1 × 1 cm (orthographic), far from the slab's edges.
        s.camera((-5.0 * math.sin(to), 5.0 * math.cos(to), 0.0), (0.0, 0.0, 0.0), ortho=1.0)
        px = math.pi * s.render("CYCLES", 4 if direct_only else spp, 1, direct_only).reshape(-1, 3)
        px /= math.cos(ti)
        return [float(x) for x in px.mean(0)], [float(x) for x in px.std(0, ddof=1) / math.sqrt(px.shape[0])]

    t0 = time.time()
    calibration = {f"light {li:.0f}°, view {vi:.0f}°": render(lambda s: s.diffuse([1.0] * 3), li, vi, direct_only=True)[0]
                   for li, vi in [(0, 0), (60, 35)]}
    cal_ok = all(abs(x - 1) <= SLAB_CALIBRATION for v in calibration.values() for x in v)
    print("calibration: an opaque white Lambertian slab, π × radiance / irradiance "
          + ", ".join(f"{k}: " + "/".join(f"{x:.4f}" for x in v) for k, v in calibration.items())
          + f" (must be 1 within {100 * SLAB_CALIBRATION:.1f} %): {'passes' if cal_ok else 'FAILS'}", flush=True)
    ok, checks, reported = cal_ok, [], []
    if a.g:
        return g_sweep(a, sss, m, render, calibration, cal_ok, bpy, t0)

    def line(what, ratio, se, required=None):
        print(f"  {what:<72} " + "/".join(f"{x:.3f} ± {e:.3f}" for x, e in zip(ratio, se))
              + ("" if required is None else f": {'within' if required else 'NOT within'} {100 * SLAB_TOLERANCE:.0f} %"),
              flush=True)

    def ratio(x, y):
        (a_, sa), (b_, sb) = x, y
        r = [p / q for p, q in zip(a_, b_)]
        return r, [v * math.hypot(e / p, f / q) for v, p, e, q, f in zip(r, a_, sa, b_, sb)]
    with tempfile.TemporaryDirectory() as tmp:
        for eta in sorted({1.0, own_eta}):
            path = material_toml(m, eta, os.path.join(tmp, f"slab{eta}.toml"))
            mc = incidence_rd(sss, path, refracted if eta == 1.0 else views, a.photons, tmp)
            burley, walk = engine_params(sss, path)
            rw = lambda s: s.principled(walk, "RANDOM_WALK", eta)
            print(f"η = {eta}: Cycles (π × radiance / irradiance) over mc's total diffuse reflectance Rd(θ), R/G/B")
            if eta == 1.0:
                # The walk starts on the camera's side, refracting the view ray, and reaches the
                # light through a diffuse BSDF where it leaves (subsurface_bounce,
                # subsurface_shader_data_setup): under normal light, π × radiance / irradiance
                # seen from θ is the escape probability of a walk entering at θt, which is mc's
                # Rd(θt) if Cycles traces the material's own σa, σs, g: the parameters' test.
                cycles = [render(rw, 0.0, v) for v in views]
                for v, t, c, d in zip(views, refracted, cycles, mc):
                    r, se = ratio(c, d)
                    passed = all(abs(x - 1) <= SLAB_TOLERANCE for x in r)
                    ok &= passed
                    checks.append({"what": f"random walk, light 0°, view {v:.1f}°, over Rd({t:.1f}°)", "ratio": r,
                                   "ratio_se": se, "pass": passed})
                    line(f"random walk, light 0°, view {v:4.1f}° / Rd({t:4.1f}°)", r, se, passed)
                # Total reflectance of a half-space does not depend on lengths (Rd(σa, σs) is a
                # function of σs/σt alone): a thin slab does, so it tests the radius. Light that
                # leaves through its underside does not come back (Cycles: it exits there, facing
                # away from the light; mc: the layer between two index-matched half-spaces).
                path = material_toml(m, 1.0, os.path.join(tmp, "thin.toml"), THIN_SLAB)
                run([sss, "simulate", path, "--photons", str(a.photons), "--profile-only", "--out", tmp])
                thin = json.load(open(os.path.join(tmp, "thin.summary.json")))["channels"]
                thin = ([thin[c]["rd"] for c in "RGB"], [thin[c]["rd_se"] for c in "RGB"])
                r, se = ratio(render(rw, 0.0, 0.0, thickness=THIN_SLAB), thin)
                passed = all(abs(x - 1) <= SLAB_TOLERANCE for x in r)
                ok &= passed
                checks.append({"what": f"random walk on a {THIN_SLAB} cm slab, light 0°, view 0°, over its Rd",
                               "ratio": r, "ratio_se": se, "pass": passed})
                line(f"random walk on a {THIN_SLAB} cm slab, light 0°, view 0° / its Rd", r, se, passed)
                r, se = ratio(mc[0], thin)
                reported.append({"what": f"half-space Rd(0°) over the {THIN_SLAB} cm slab's (what lengths change)",
                                 "eta": eta, "ratio": r, "ratio_se": se})
                line(f"(mc: half-space Rd(0°) / the {THIN_SLAB} cm slab's)", r, se)
                # What Cycles does not model: the light's side is diffuse, so its total reflectance
                # is the white-sky albedo Σ w·Rd(θ) at every incidence, not Rd(θ_light).
                total = [sum(w * c[0][k] for w, c in zip(weights, cycles[1:])) for k in range(3)]
                total_se = [math.sqrt(sum((w * c[1][k]) ** 2 for w, c in zip(weights, cycles[1:]))) for k in range(3)]
                for name, (r, se) in [("reflected energy under normal light / Rd(0°)", ratio((total, total_se), mc[0])),
                                      ("light 60°, view 0° / the same at light 0° (incidence-blind: 1)",
                                       ratio(render(rw, 60.0, 0.0), cycles[0]))]:
                    reported.append({"what": f"random walk, {name}", "eta": eta, "ratio": r, "ratio_se": se})
                    line(f"random walk, {name}", r, se)
            else:
                r, se = ratio(render(rw, 0.0, 0.0), mc[0])
                reported.append({"what": "random walk, light 0°, view 0° / Rd(0°) (no internal reflection)", "eta": eta, "ratio": r, "ratio_se": se})
                line("random walk, light 0°, view 0° / Rd(0°) (no internal reflection)", r, se)
            r, se = ratio(render(lambda s: s.principled(burley, "BURLEY", eta), 0.0, 0.0), mc[0])
            reported.append({"what": "Christensen-Burley, light 0°, view 0° / Rd(0°)", "eta": eta, "ratio": r, "ratio_se": se})
            line("Christensen-Burley, light 0°, view 0° / Rd(0°)", r, se)
    result = {"material": a.material, "blender": bpy.app.version_string, "resolution": res, "spp": spp,
              "incidence_photons": a.photons, "calibration": calibration, "calibration_pass": cal_ok,
              "checks": checks, "reported": reported, "pass": ok, "seconds": time.time() - t0}
    if a.json:
        os.makedirs(os.path.dirname(os.path.abspath(a.json)), exist_ok=True)
        with open(a.json, "w") as f:
            json.dump(result, f, indent=2)
    print(f"slab: {'agrees' if ok else 'DISAGREES'} ({time.time() - t0:.0f} s)")
    return 0 if ok else 1


def g_sweep(a, sss, m, render, calibration, cal_ok, bpy, t0):
    """`slab --g LIST`: the material's σa and σs with each anisotropy g of LIST in every channel,
    index-matched, on the thick slab under normal light, seen at 0°: Cycles' reflectance (Random
    Walk with engine-params' fields, which match Base Color to the walk Cycles really runs) over
    `sss simulate`'s Rd(0°) of the exact medium, required within SWEEP_TOLERANCE per channel."""
    ok, sweep = cal_ok, []
    print(f"g sweep: {a.material}'s σa, σs with g replaced, η = 1; Cycles (view 0°, light 0°) over mc's Rd(0°), R/G/B")
    with tempfile.TemporaryDirectory() as tmp:
        for g in [float(x) for x in a.g.split(",")]:
            mg = json.loads(json.dumps(m))
            for c in "RGB":
                mg["channels"][c]["g"] = g
            path = material_toml(mg, 1.0, os.path.join(tmp, f"g{g}.toml"))
            mc = incidence_rd(sss, path, [0.0], a.photons, tmp)[0]
            _, walk = engine_params(sss, path)
            c = render(lambda s: s.principled(walk, "RANDOM_WALK", 1.0), 0.0, 0.0)
            r = [p / q for p, q in zip(c[0], mc[0])]
            se = [v * math.hypot(e / p, f / q) for v, p, e, q, f in zip(r, c[0], c[1], mc[0], mc[1])]
            passed = all(abs(x - 1) <= SWEEP_TOLERANCE for x in r)
            ok &= passed
            sweep.append({"g": g, "cycles": c[0], "cycles_se": c[1], "mc_rd": mc[0], "mc_rd_se": mc[1],
                          "ratio": r, "ratio_se": se, "base_color": walk["Base Color"], "pass": passed})
            print(f"  g = {g:<4}  Cycles " + "/".join(f"{x:.4f}" for x in c[0]) + "  mc Rd(0°) "
                  + "/".join(f"{x:.4f}" for x in mc[0]) + "  ratio " + "/".join(f"{x:.4f} ± {e:.4f}" for x, e in zip(r, se))
                  + f": {'within' if passed else 'NOT within'} {100 * SWEEP_TOLERANCE:.0f} %", flush=True)
    result = {"material": a.material, "blender": bpy.app.version_string, "resolution": a.resolution, "spp": a.spp,
              "incidence_photons": a.photons, "calibration": calibration, "calibration_pass": cal_ok,
              "g_sweep": sweep, "pass": ok, "seconds": time.time() - t0}
    if a.json:
        os.makedirs(os.path.dirname(os.path.abspath(a.json)), exist_ok=True)
        with open(a.json, "w") as f:
            json.dump(result, f, indent=2)
    print(f"slab --g: {'agrees' if ok else 'DISAGREES'} ({time.time() - t0:.0f} s)")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sss", help="path to the sss binary [default: target/release/sss]")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("slab", help="Cycles' reflected energy on a thick slab against `sss simulate` (CI)")
    p.add_argument("--material", default="skin1", help="built-in material [default: skin1]")
    p.add_argument("--resolution", type=int, default=24, help="image side [px; default 24]")
    p.add_argument("--spp", type=int, default=64, help="Cycles' samples per pixel [default 64]")
    p.add_argument("--photons", type=int, default=300_000,
                   help="`sss simulate` photons per channel and angle [default 3e5]")
    p.add_argument("--g", help="comma-separated anisotropies, e.g. 0,0.5,0.8,0.9: instead of the checks above, the "
                   "material's σa, σs with each g, index-matched, Cycles' Rd(0°) within 1 %% of mc's (use --spp 1024)")
    p.add_argument("--json", help="also write the numbers to this file")
    p = sub.add_parser("scene", help="images.py's scenes in Blender, scored against its Mitsuba reference")
    p.add_argument("--scene", default="sphere", choices=["sphere", "fin", "bust"])
    p.add_argument("--material", default="skin1", help="built-in material [default: skin1]")
    p.add_argument("--out", default="out/references", help="images.py's --out [default: out/references]")
    p.add_argument("--spp", type=int,
                   help=f"samples per pixel [default: the Mitsuba reference's; EEVEE at most {EEVEE_SAMPLES}]")
    p.add_argument("--renderers", default=",".join(RENDERERS),
                   help=f"comma-separated, of {', '.join(RENDERERS)} [default: all]")
    a = ap.parse_args()
    return slab_command(a) if a.command == "slab" else scene_command(a)


if __name__ == "__main__":
    sys.exit(main())

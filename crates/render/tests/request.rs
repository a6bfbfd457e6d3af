//! The request as a whole: its defaults (the method closest to path tracing), the refusals of
//! what does not go together (each naming the field), the named choices both front ends read,
//! the text forms of lights and boxes, and a plan built without a device.

use render::{
    Choice, DipoleEnergy, ExitLaw, Plan, RenderError, Request, ShadingOptions, Simulated,
};

/// The field a refusal names, or the error's text when it is not a refusal.
fn field_of(e: RenderError) -> String {
    match e.renamed(|_| None) {
        RenderError::Invalid { field, .. } => field,
        e => format!("not a refusal: {e}"),
    }
}

fn with_method(method: gpu::Method) -> Request {
    let mut r = Request::default();
    r.frame.method = method;
    r
}

#[test]
fn the_default_is_the_separable_kernel_with_every_table() {
    let r = Request::default();
    assert_eq!(r.method(), gpu::Method::Separable);
    let s = r.resolved_shading();
    assert!(s.incidence && s.entry_shift && s.translucency);
    assert_eq!(s.exit, ExitLaw::Entry);
    // The plain kernel stays one option per table away.
    let plain = Request {
        shading: ShadingOptions {
            incidence: Some(false),
            exit: Some(ExitLaw::Lambertian),
            entry_shift: Some(false),
            translucency: Some(false),
            shape: Some(false),
        },
        ..Request::default()
    };
    let s = plain.resolved_shading();
    assert!(!s.incidence && !s.entry_shift && !s.translucency);
    assert_eq!(s.exit, ExitLaw::Lambertian);
}

#[test]
fn the_other_methods_default_to_their_own_physics() {
    for m in [
        gpu::Method::DirectionalDipole,
        gpu::Method::AreaGather,
        gpu::Method::SurfaceGather,
    ] {
        let r = with_method(m);
        let s = r.resolved_shading();
        assert!(!s.incidence && !s.entry_shift && !s.translucency, "{m:?}");
        assert_eq!(s.exit, ExitLaw::Lambertian, "{m:?}");
        r.check().unwrap();
    }
    let r = Request {
        no_sss: true,
        ..Request::default()
    };
    let s = r.resolved_shading();
    assert!(!s.incidence && !s.entry_shift && !s.translucency);
}

#[test]
fn what_does_not_go_together_is_refused_by_name() {
    let mut dipole_incidence = with_method(gpu::Method::DirectionalDipole);
    dipole_incidence.shading.incidence = Some(true);
    let mut surface_exit = with_method(gpu::Method::SurfaceGather);
    surface_exit.shading.exit = Some(ExitLaw::Entry);
    let mut area_translucency = with_method(gpu::Method::AreaGather);
    area_translucency.shading.translucency = Some(true);
    let mut surface_frames = with_method(gpu::Method::SurfaceGather);
    surface_frames.gather.frames = 0;
    let mut two_materials = Request::default();
    two_materials.frame.scene = "pair".into();
    two_materials
        .materials
        .push(two_materials.materials[0].clone());
    two_materials.kernel = Some(fit::taps::ShaderKernel {
        model: fit::KernelModel::Preint,
        material: "x".into(),
        unit: "cm".into(),
        taps: 1,
        range: 0.1,
        jitter: 0.0,
        pass: Vec::new(),
    });
    let mut no_photons = Request::default();
    no_photons.tables.incidence_photons = 0;
    let mut pair_one_material = Request::default();
    pair_one_material.frame.scene = "pair".into();
    let mut width = Request::default();
    width.frame.width = 0;
    for (r, field) in [
        (dipole_incidence, "incidence"),
        (surface_exit, "exit"),
        (area_translucency, "translucency"),
        (surface_frames, "frames"),
        (two_materials, "kernel"),
        (no_photons, "incidence_photons"),
        (pair_one_material, "materials"),
        (width, "width"),
    ] {
        assert_eq!(field_of(r.check().unwrap_err()), field);
    }
    // Saying "off" to what a method does not use is no error.
    let mut dipole_off = with_method(gpu::Method::DirectionalDipole);
    dipole_off.shading = ShadingOptions {
        incidence: Some(false),
        exit: Some(ExitLaw::Lambertian),
        entry_shift: Some(false),
        translucency: Some(false),
        shape: Some(false),
    };
    dipole_off.check().unwrap();
}

/// Every choice's names parse back to their values, no two alike; anything else is refused,
/// naming the choice.
fn round_trips<T: Choice + std::fmt::Debug>() {
    let names: Vec<&str> = T::CHOICES.iter().map(|(n, _, _)| *n).collect();
    for (name, value, help) in T::CHOICES {
        assert_eq!(T::parse(name).unwrap(), *value);
        assert_eq!(T::parse(&name.to_uppercase()).unwrap(), *value);
        assert_eq!(value.name(), *name);
        assert!(!help.is_empty());
        assert_eq!(names.iter().filter(|n| *n == name).count(), 1, "{name}");
    }
    assert_eq!(field_of(T::parse("no-such-choice").unwrap_err()), T::WHAT);
}

#[test]
fn every_choice_round_trips_through_its_name() {
    round_trips::<gpu::Method>();
    round_trips::<ExitLaw>();
    round_trips::<DipoleEnergy>();
    round_trips::<shading::Bssrdf>();
    round_trips::<gpu::AlbedoMode>();
    round_trips::<gpu::DepthMode>();
}

#[test]
fn lights_points_and_boxes_parse_or_say_what_was_expected() {
    use render::parse::{cuboid, light, vec3};
    assert_eq!(vec3("1, 2,3").unwrap(), glam::Vec3::new(1.0, 2.0, 3.0));
    assert!(vec3("1,2").unwrap_err().contains("X,Y,Z"));
    assert!(vec3("1,2,inf").is_err());
    assert!(cuboid("0,0,0:1,1,1").is_ok());
    assert!(cuboid("1,0,0:0,1,1").unwrap_err().contains("MIN"));
    match light("dir:0,2,0").unwrap() {
        gpu::Light::Directional {
            towards,
            irradiance,
            ..
        } => {
            assert_eq!(towards, glam::Vec3::Y);
            assert_eq!(irradiance, glam::Vec3::splat(1.2));
        }
        l => panic!("{l:?}"),
    }
    assert!(light("dir:0,0,0").unwrap_err().contains("zero"));
    assert!(light("sun:1,2,3").unwrap_err().contains("dir:"));
    assert!(light("point:0,1,0:-1").unwrap_err().contains("≥ 0"));
}

/// A plan needs no device: the tables are `shading`'s for the request's seed (built again here
/// from the same spec, the same numbers), the exit law `on` repeats the normal-entry row for
/// every entry angle, and the separable method gets one kernel per material.
#[test]
fn a_plan_holds_the_tables_the_request_asks_for() {
    let mut r = Request::default();
    r.frame.width = 64;
    r.frame.height = 64;
    r.tables.config.photons = 20_000;
    r.tables.incidence_photons = 2_000;
    r.tables.translucency_photons = 1_000;
    r.shading.exit = Some(ExitLaw::Normal);
    let mut profiles = Simulated {
        tables: &r.tables.clone(),
        progress: &(),
    };
    let plan = Plan::build(&r, &mut profiles, &()).unwrap();
    assert_eq!(plan.kernels.len(), 1);
    assert!(plan.gather.is_none());
    let spec = r
        .tables
        .config
        .batch(&[&r.materials[0].material], 2_000, r.tables.seed, true)
        .unwrap();
    let angles = shading::AngleTables::from_mc(&spec, true, true, &|_| {}).unwrap();
    let s = &plan.params.shading[0];
    assert_eq!(s.incidence, angles.incidence);
    for row in &s.exit {
        assert_eq!(*row, angles.exit[0]);
    }
    assert!(s.translucency.is_some());
    assert_eq!(s.eta, r.materials[0].material.eta as f32);
    let shift = shading::EntryShift::from_mc(&spec, &|_| {}).unwrap();
    assert_eq!(s.entry_shift.shift_cm, shift.shift_cm);
    assert!(render::describe(&plan).contains("entry shift"));
}

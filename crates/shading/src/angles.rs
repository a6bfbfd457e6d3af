//! The angle tables' grid, θ = 0°, 10°, …, 80° (incidence, exit, transmitted-exit and
//! entry-shift tables): the CPU twin of `wgsl/angles.wgsl`.

/// Entries of an angle table ([`crate::Shading::incidence`], each axis of
/// [`crate::Shading::exit`], [`crate::EntryShift`]): θ = 0°, 10°, …, 80°.
pub const INCIDENCE_STEPS: usize = 9;

/// The WGSL of the angle grid, `angle_index(cos_t) -> vec2<f32>` (entry and weight of the next),
/// and of a table's lookup, `angle_table(table, cos_a) -> vec3<f32>`, prepended to every shader
/// that reads an angle table.
pub const ANGLES_WGSL: &str = include_str!("wgsl/angles.wgsl");

/// An angle table at cos θ = `cos_i`: ρ(θ)/ρ(0) from an incidence table, h(θ) from an exit
/// table, δ(θ) from an entry shift; linear in θ between entries, the 80° entry beyond (also for
/// cos θ ≤ 0), as the shaders' `angle_index` reads it.
pub fn incidence_ratio(table: &[[f32; 3]; INCIDENCE_STEPS], cos_i: f32) -> [f32; 3] {
    let t = cos_i.clamp(0.0, 1.0).acos().to_degrees() / 10.0;
    let i = (t.floor() as usize).min(INCIDENCE_STEPS - 1);
    if i + 1 >= INCIDENCE_STEPS {
        return table[INCIDENCE_STEPS - 1];
    }
    let f = t - i as f32;
    [0, 1, 2].map(|c| table[i][c] * (1.0 - f) + table[i + 1][c] * f)
}

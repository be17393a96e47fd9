//! The density errors of a split (`dualsph_refinement::density_error`) over the offset ε and
//! the children's radius ratio α, for the kernels and supports the scenes use:
//! `cargo run --release -p dualsph-refinement --example split_errors`.
use dualsph_core::kernels::KernelKind;
use dualsph_core::math::{Real, Vec1, Vector};
use dualsph_refinement::density_error::{
    front_gather_error, split_density_error, split_gather_error,
};
use glam::{DVec2, DVec3};

const OFFSETS: [Real; 5] = [0.15, 0.2, 0.25, 0.3, 0.35];
const ALPHAS: [Real; 4] = [0.5, 0.7, 0.9, 1.0];

fn table<V: Vector>(kind: KernelKind, hf: Real) {
    println!(
        "\n{kind:?}, h = {hf} sizes, {}-D: single split / front (gather), scatter",
        V::DIM
    );
    println!("| ε | {} |", ALPHAS.map(|a| format!("α = {a}")).join(" | "));
    println!("|---|{}", "---|".repeat(ALPHAS.len()));
    for eps in OFFSETS {
        let cells: Vec<String> = ALPHAS
            .iter()
            .map(|&a| {
                let scatter = if V::DIM == 2 {
                    format!(", {:.3}", split_density_error::<V>(kind, hf, eps, a, 80))
                } else {
                    String::new()
                };
                format!(
                    "{:.3} / {:.3}{scatter}",
                    split_gather_error::<V>(kind, hf, eps, a),
                    front_gather_error::<V>(kind, hf, eps, a)
                )
            })
            .collect();
        println!("| {eps} | {} |", cells.join(" | "));
    }
}

fn main() {
    for (kind, hf) in [
        (KernelKind::WendlandC2, 3.0),
        (KernelKind::CubicSpline, 2.0),
    ] {
        table::<Vec1>(kind, hf);
        table::<DVec2>(kind, hf);
        table::<DVec3>(kind, hf);
    }
}

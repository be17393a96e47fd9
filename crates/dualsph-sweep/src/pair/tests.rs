use super::*;
use dualsph_core::kernels::{Kernel, KernelKind};
use glam::{DVec2, DVec3};

#[test]
fn owner_kernel_matches_kernel_to_round_off() {
    for kind in KernelKind::ALL {
        // The viscosity kernel cannot be normalised in 1-D (scenes refuse it there).
        for dim in (1..=3).filter(|&d| kind.supports_dimension(d)) {
            let kernel = Kernel::new(kind, dim);
            for h in [0.013, 0.7, 2.9] {
                let k = OwnerKernel::new(&kernel, h);
                // Müller's viscosity profile −q³/2 + q² + 1/(2q) − 1 cancels to 0 at q = 1, so
                // near the edge round-off is relative to the kernel's scale C_d/h^d, not to
                // the tiny value; the other profiles are products of (1 − q) and need no floor.
                let hd = h.powi(dim as i32);
                let (w_floor, g_floor) = if kind == KernelKind::MullerViscosity {
                    (kernel.norm / hd, kernel.norm / (hd * h))
                } else {
                    (1e-300, 0.0)
                };
                for i in 0..200 {
                    let r = h * i as Real / 200.0;
                    let (w0, w1) = (kernel.w(r, h), k.w(r));
                    if w0.is_finite() {
                        assert!((w0 - w1).abs() <= 1e-13 * w0.abs().max(w_floor), "{kind:?}");
                    } else {
                        // The viscosity kernel is singular at r = 0: both must say so.
                        assert_eq!(w0, w1, "{kind:?} {dim}D at r = 0");
                    }
                    let x = DVec3::new(0.6, -0.48, 0.64) * r;
                    let (g0, g1) = (kernel.grad(x, r, h), k.grad(x, r));
                    assert!(
                        (g0 - g1).length() <= 1e-13 * g0.length().max(g_floor),
                        "{kind:?} {dim}D"
                    );
                    let y = DVec2::new(0.8, -0.6) * r;
                    assert_eq!(k.eval(y, r).1, k.grad(y, r));
                }
            }
        }
    }
}

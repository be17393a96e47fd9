//! Adaptive resolution in a gas (`scenes/sod_1d_adaptive.ron`): the refinement follows the
//! shock and the contact of Sod's tube as they move apart, against the exact Riemann solution's
//! wave positions, leaves the constant states coarse, and keeps mass, momentum and total
//! energy to round-off through its splits.

use crate::common;

use dualsph_validation::report::sod::{adaptive_level as level, exact, wave_windows};
use dualsph_validation::report::{CaseSpec, Recording};

/// The finest level of the scene's ladder (`coarsest/finest` = 4 in 1-D).
const FINEST: f64 = 2.0;

#[test]
fn sod_refinement_follows_the_shock_and_the_contact_and_conserves() {
    let opts = common::report_options(1.0, None);
    let spec = CaseSpec::new("adaptive", opts.scene("sod_1d_adaptive.ron").unwrap(), None);
    let times = [0.05, 0.1, 0.15, 0.2];
    let rec = Recording {
        every: 10,
        snapshot_times: times.to_vec(),
        ..Default::default()
    };
    let run = opts.run(&spec, &rec).unwrap();
    assert!(run.failure.is_none(), "{:?}", run.failure);
    let r = exact();
    for (_, t, table) in &run.snapshots {
        let [fan, contact, shock] = wave_windows(&r, *t);
        let (contact, shock) = (0.5 * (contact.0 + contact.1), 0.5 * (shock.0 + shock.1));
        let mut near_waves = 0;
        for p in table.rows() {
            let x = p.pos()[0];
            // within a finest-particle support of the contact and of the shock: the finest
            if (x - contact).abs() < 0.005 || (x - shock).abs() < 0.005 {
                assert_eq!(level(&p), FINEST, "t = {t}: x = {x} is not refined");
                near_waves += 1;
            }
            // the constant states ahead of the rarefaction and of the shock, inside the
            // graded window: the coarsest
            let ahead = x < fan.0 - 0.05 || x > shock + 0.05;
            if ahead && x.abs() < 0.5 {
                assert_eq!(level(&p), 0.0, "t = {t}: x = {x} was refined");
            }
        }
        assert!(
            near_waves >= 8,
            "t = {t}: {near_waves} particles by the waves"
        );
    }
    assert_eq!(run.snapshots.len(), times.len());
    // splits only: mass, momentum and total energy to round-off
    let (first, last) = (&run.diagnostics[0], run.final_diagnostics());
    assert!((last.mass - first.mass).abs() < 1e-14 * first.mass);
    assert!(last.momentum[0].abs() < 1e-14 * last.momentum_scale);
    assert!((last.e_tot - first.e_tot).abs() < 1e-13 * first.e_tot);
}

//! Unit tests of the equations of state and the plugin's settings.
use super::*;

/// The inlined binary exponentiation is bitwise `f64::powi` with a run-time exponent.
#[test]
fn inlined_powi_is_bitwise_f64_powi() {
    let xs = [
        0.0,
        0.5,
        0.987654321,
        1.0,
        1.0123456789,
        1.5,
        3.0,
        1e-3,
        7.77e2,
    ];
    for &x in &xs {
        for n in -16..=16 {
            let n_opaque = std::hint::black_box(n);
            assert_eq!(powi(x, n).to_bits(), x.powi(n_opaque).to_bits(), "{x}^{n}");
        }
    }
    assert_eq!(
        pow(1.01, 7.0).to_bits(),
        1.01f64.powi(std::hint::black_box(7)).to_bits()
    );
    assert_eq!(pow(1.01, 0.5), libm::pow(1.01f64, 0.5));
}

/// The γ = 7 shortcut against the runtime's `powi` (through [`pow`]) on densities around
/// and far from ρ0: bitwise equal.
#[test]
fn water_powers_are_bitwise_pow_7_and_3() {
    let mut x = 0.25;
    while x < 4.0 {
        let (x7, x3) = water_powers(x);
        assert_eq!(x7.to_bits(), pow(x, 7.0).to_bits(), "{x}^7");
        assert_eq!(x3.to_bits(), pow(x, 3.0).to_bits(), "{x}^3");
        x += 0.000_123_456_7;
    }
}

#[test]
fn tait_reference_state_and_sound_speed() {
    let e = Eos::Tait {
        rho0: 1000.0,
        gamma: 7.0,
        p0: 100.0f64.powi(2) * 1000.0 / 7.0,
        c0: 100.0,
        p_min: Real::NEG_INFINITY,
        p_b: 0.0,
        rho_min: Real::NEG_INFINITY,
    };
    assert_eq!(e.eval(1000.0, 0.0), (0.0, 100.0));
    assert!(e.eval(990.0, 0.0).0 < 0.0);
    // c² = dp/dρ, checked by a central difference
    let (d, rho) = (1e-4, 1010.0);
    let dp = (e.eval(rho + d, 0.0).0 - e.eval(rho - d, 0.0).0) / (2.0 * d);
    let c = e.eval(rho, 0.0).1;
    assert!((dp - c * c).abs() < 1e-6 * c * c);
}

#[test]
fn tait_floor_cuts_tension_only() {
    let (p0, c0) = (100.0f64.powi(2) * 1000.0 / 7.0, 100.0);
    let free = Eos::Tait {
        rho0: 1000.0,
        gamma: 7.0,
        p0,
        c0,
        p_min: Real::NEG_INFINITY,
        p_b: 0.0,
        rho_min: Real::NEG_INFINITY,
    };
    let floored = Eos::Tait {
        rho0: 1000.0,
        gamma: 7.0,
        p0,
        c0,
        p_min: 0.0,
        p_b: 0.0,
        rho_min: Real::NEG_INFINITY,
    };
    assert_eq!(floored.eval(990.0, 0.0).0, 0.0);
    assert_eq!(floored.eval(990.0, 0.0).1, free.eval(990.0, 0.0).1);
    assert_eq!(floored.eval(1010.0, 0.0), free.eval(1010.0, 0.0));
}

#[test]
fn ideal_gas_sod_states() {
    let e = Eos::Ideal { gamma: 5.0 / 3.0 };
    assert!((e.eval(1.0, 1.5).0 - 1.0).abs() < 1e-15);
    assert!((e.eval(0.125, 1.2).0 - 0.1).abs() < 1e-15);
}

#[test]
fn materials_name_declared_bodies_once_with_one_scale() {
    let info = SceneInfo {
        bodies: vec!["water".into(), "light".into()],
        ..SceneInfo::of_dimension(2)
    };
    let material = |body: &str, c0: Option<Real>, p0: Option<Real>| TaitMaterial {
        body: body.into(),
        rho0: 500.0,
        c0: c0.map(SoundSpeedSetting::Value),
        p0,
    };
    let eos = |materials| TaitEos {
        rho0: 1000.0,
        gamma: 7.0,
        c0: Some(20.0.into()),
        p0: None,
        min_pressure: None,
        cavitation: false,
        background: 0.0,
        materials,
    };
    let check = |m| SimPlugin::validate(&eos(m), &info);
    assert!(check(vec![material("light", Some(20.0), None)]).is_ok());
    let e = check(vec![material("oil", Some(20.0), None)]).unwrap_err();
    assert!(
        e.starts_with("materials[0].body: no body named `oil`"),
        "{e}"
    );
    let twice = vec![
        material("light", Some(20.0), None),
        material("light", None, Some(1.0)),
    ];
    assert!(
        check(twice)
            .unwrap_err()
            .contains("materials[1].body: `light` is given twice")
    );
    let e = check(vec![material("light", Some(20.0), Some(1.0))]).unwrap_err();
    assert!(
        e.contains("materials[0].c0, materials[0].p0: give exactly one"),
        "{e}"
    );
}

/// `cavitation: true` floors the pressure at 0 and the density where Eq. 7.5 gives 0, and
/// leaves the law above it bitwise as it was; with a background pressure that density is
/// below ρ0. A `min_pressure` beside it is the cavitation pressure: the pressure is floored
/// there and the density where the law gives it; one beyond the law's largest tension
/// (−p0) is refused.
#[test]
fn cavitation_floors_density_where_the_pressure_vanishes() {
    let plugin = |cavitation: bool, background: Real, min_pressure: Option<Real>| TaitEos {
        rho0: 1000.0,
        gamma: 7.0,
        c0: Some(20.0.into()),
        p0: None,
        min_pressure,
        cavitation,
        background,
        materials: Vec::new(),
    };
    let law = |t: TaitEos| t.tait(1000.0, Some(20.0), None).unwrap();
    let (free, cav) = (law(plugin(false, 0.0, None)), law(plugin(true, 0.0, None)));
    assert_eq!(cav.floored(900.0), 1000.0);
    assert_eq!(cav.eval(cav.floored(900.0), 0.0), (0.0, 20.0));
    for rho in [1000.0, 1000.1, 1234.5] {
        assert_eq!(cav.floored(rho), rho);
        assert_eq!(cav.eval(rho, 0.0), free.eval(rho, 0.0));
    }
    assert_eq!(free.floored(1e-3), 1e-3);
    assert!(cav.floored(Real::NAN).is_nan());
    assert_eq!(Eos::Ideal { gamma: 1.4 }.floored(1e-3), 1e-3);
    // p_b = 0.1 p0: p = 0 at ρ0 (0.9)^(1/7)
    let p0 = 20.0 * 20.0 * 1000.0 / 7.0;
    let with_b = law(plugin(true, 0.1 * p0, None));
    let rho_c = with_b.floored(0.0);
    assert!(
        (rho_c - 1000.0 * libm::pow(0.9_f64, 1.0 / 7.0)).abs() < 1e-9,
        "{rho_c}"
    );
    assert!(with_b.eval(rho_c, 0.0).0.abs() < 1e-9 * p0);
    assert_eq!(with_b.eval(0.99 * rho_c, 0.0).0, 0.0);
    let info = SceneInfo::of_dimension(2);
    assert!(SimPlugin::validate(&plugin(true, 0.0, Some(-5e3)), &info).is_ok());
    // water's vapour pressure under the atmosphere, p_c = −0.5 p0 here
    let p_c = -0.5 * p0;
    let vapour = law(plugin(true, 0.0, Some(p_c)));
    let rho_c = vapour.floored(0.0);
    assert!(
        (rho_c - 1000.0 * libm::pow(0.5_f64, 1.0 / 7.0)).abs() < 1e-9,
        "{rho_c}"
    );
    assert!((vapour.eval(rho_c, 0.0).0 - p_c).abs() < 1e-9 * p0);
    assert_eq!(vapour.eval(0.9 * rho_c, 0.0).0, p_c);
    assert_eq!(vapour.eval(1010.0, 0.0), free.eval(1010.0, 0.0));
    let e = plugin(true, 0.0, Some(-1.5 * p0))
        .tait(1000.0, Some(20.0), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("below the largest tension"), "{e}");
}

use super::*;

/// Records of a resting 2-D block [0, 1] × [0, 0.5], spacing 0.02, ρ = 1000 + 100 y.
fn block() -> Vec<ParticleRecord> {
    let dx = 0.02;
    let mut out = Vec::new();
    for j in 0..25 {
        for i in 0..50 {
            let (x, y) = ((i as Real + 0.5) * dx, (j as Real + 0.5) * dx);
            out.push(ParticleRecord {
                id: out.len() as u64,
                pos: [x, y, 0.0],
                vel: [0.0; 3],
                mass: 1000.0 * dx * dx,
                rho: 1000.0 + 100.0 * y,
                p: 0.0,
                e: 0.0,
                h: 2.0 * dx,
            });
        }
    }
    out
}

#[test]
fn grid_of_a_block_is_inside_where_the_fluid_is() {
    let recs = block();
    let bounds = Some(([0.0, 0.0, 0.0], [2.0, 1.0, 0.0]));
    let f = sample_records(
        &recs,
        2,
        KernelKind::CubicSpline,
        Quantity::Density,
        0.05,
        bounds,
    )
    .unwrap();
    assert_eq!(f.grid.dims, [41, 21, 1]);
    for n in 0..f.grid.len() {
        let [x, y, _] = f.grid.point(n);
        let deep_inside = x > 0.06 && x < 0.94 && y > 0.06 && y < 0.44;
        let far_outside = x > 1.05 || y > 0.55;
        if deep_inside {
            let v = f.values[n].expect("inside");
            // Shepard interpolation of a field that is linear in y: within 0.1 % of 1000 + 100 y
            assert!((v - (1000.0 + 100.0 * y)).abs() < 1.0, "({x}, {y}): {v}");
        }
        if far_outside {
            assert!(f.values[n].is_none() && f.shepard[n] == 0.0);
        }
    }
}

#[test]
fn vti_and_png_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let (vti, png) =
        write_density_grid(&block(), 2, KernelKind::CubicSpline, 0.02, dir.path()).unwrap();
    let binary = std::fs::read(&vti).unwrap();
    assert!(String::from_utf8_lossy(&binary).contains("<AppendedData encoding=\"raw\">"));
    // the same field in ASCII, to read its values
    let f = sample_records(
        &block(),
        2,
        KernelKind::CubicSpline,
        Quantity::Density,
        0.02,
        None,
    )
    .unwrap();
    write_vti(&vti, &f, VtkEncoding::Ascii).unwrap();
    let text = std::fs::read_to_string(&vti).unwrap();
    assert!(text.starts_with("<?xml"));
    assert!(text.contains("type=\"ImageData\"") && text.trim_end().ends_with("</VTKFile>"));
    // the grid covers the block grown by h = 0.04: [−0.03, 1.03] × [−0.03, 0.53] → 54 × 29
    assert!(
        text.contains("WholeExtent=\"0 53 0 28 0 0\""),
        "{}",
        &text[..300]
    );
    let density: Vec<Real> = text
        .split("Name=\"Density\" format=\"ascii\">")
        .nth(1)
        .unwrap()
        .split("</DataArray>")
        .next()
        .unwrap()
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(density.len(), 54 * 29);
    assert!(density.iter().any(|&v| (v - 1025.0).abs() < 5.0));
    assert!(std::fs::metadata(&png).unwrap().len() > 2000);
}

#[test]
fn bad_arguments_are_errors() {
    let r = block();
    let k = KernelKind::CubicSpline;
    assert!(sample_records(&r, 2, k, Quantity::Density, 0.0, None).is_err());
    assert!(sample_records(&r, 2, k, Quantity::Density, 10.0, None).is_err());
    assert!(sample_records(&[], 2, k, Quantity::Density, 0.1, None).is_err());
    assert!(
        sample_records(
            &r,
            1,
            KernelKind::MullerViscosity,
            Quantity::Density,
            0.1,
            None
        )
        .is_err()
    );
    let f1 = sample_records(&r, 1, k, Quantity::Density, 0.01, None).unwrap();
    assert!(write_png(Path::new("/nonexistent/x.png"), &f1, "t").is_err());
}

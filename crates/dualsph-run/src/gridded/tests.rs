use super::*;

/// A resting 2-D block [0, 1] × [0, 0.5], spacing 0.02, ρ = 1000 + 100 y, v = (y, 2y).
fn block() -> ParticleTable {
    let dx = 0.02;
    let (mut pos, mut vel, mut rho) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..25 {
        for i in 0..50 {
            let (x, y) = ((i as Real + 0.5) * dx, (j as Real + 0.5) * dx);
            pos.extend([x, y, 0.0]);
            vel.extend([y, 2.0 * y, 0.0]);
            rho.push(1000.0 + 100.0 * y);
        }
    }
    let n = rho.len();
    let column = |name: &str, labels: &[&str], values: Vec<Real>| dualsph_io::TableColumn {
        name: name.into(),
        labels: labels.iter().map(|l| l.to_string()).collect(),
        values,
    };
    ParticleTable {
        ids: (0..n as u64).collect(),
        columns: vec![
            column(POSITION, &["x", "y", "z"], pos),
            column("velocity", &["vx", "vy", "vz"], vel),
            column("mass", &["m"], vec![1000.0 * dx * dx; n]),
            column("density", &["rho"], rho),
            column("smoothing_length", &["h"], vec![2.0 * dx; n]),
        ],
    }
}

#[test]
fn grid_of_a_block_is_inside_where_the_fluid_is() {
    let recs = block();
    let bounds = Some(([0.0, 0.0, 0.0], [2.0, 1.0, 0.0]));
    let f = sample_table(
        &recs,
        2,
        KernelKind::CubicSpline,
        &Quantity::density(),
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
    let f = sample_table(
        &block(),
        2,
        KernelKind::CubicSpline,
        &Quantity::density(),
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
        .split("Name=\"density\" format=\"ascii\">")
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
    assert!(sample_table(&r, 2, k, &Quantity::density(), 0.0, None).is_err());
    assert!(sample_table(&r, 2, k, &Quantity::density(), 10.0, None).is_err());
    assert!(
        sample_table(
            &ParticleTable::default(),
            2,
            k,
            &Quantity::density(),
            0.1,
            None
        )
        .is_err()
    );
    assert!(
        sample_table(
            &r,
            1,
            KernelKind::MullerViscosity,
            &Quantity::density(),
            0.1,
            None
        )
        .is_err()
    );
    let f1 = sample_table(&r, 1, k, &Quantity::density(), 0.01, None).unwrap();
    assert!(write_png(Path::new("/nonexistent/x.png"), &f1, "t").is_err());
}

#[test]
fn fields_are_named_like_the_columns() {
    let t = block();
    let k = KernelKind::CubicSpline;
    let bounds = Some(([0.2, 0.1, 0.0], [0.8, 0.4, 0.0]));
    let q = |name: &str| Quantity::parse(name).unwrap();
    let vy = sample_table(&t, 2, k, &q("velocity.y"), 0.1, bounds).unwrap();
    let speed = sample_table(&t, 2, k, &q("Speed"), 0.1, bounds).unwrap();
    assert_eq!(vy.name, "velocity.y");
    for n in 0..vy.grid.len() {
        let y = vy.grid.point(n)[1];
        let v = vy.values[n].unwrap();
        assert!((v - 2.0 * y).abs() < 2e-3, "v_y({y}) = {v}");
        let s = speed.values[n].unwrap();
        assert!((s - 5f64.sqrt() * y).abs() < 3e-3, "|v|({y}) = {s}");
    }
    let sigma = sample_table(&t, 2, k, &q("shepard_sum"), 0.1, bounds).unwrap();
    assert_eq!(sigma.values[0], Some(sigma.shepard[0]));
    for (bad, expect) in [
        ("pressure", "no column `pressure`"),
        ("velocity.z", "no such component"),
        ("density.x", "no such component"),
    ] {
        let e = sample_table(&t, 2, k, &q(bad), 0.1, bounds)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(expect) && e.contains("velocity.{x,y}"),
            "{bad}: {e}"
        );
    }
}

#[test]
fn a_csv_table_is_grouped_by_the_scenes_columns() {
    let t = block();
    let flat = ParticleTable {
        ids: t.ids.clone(),
        columns: t
            .columns
            .iter()
            .flat_map(|c| {
                c.labels
                    .iter()
                    .enumerate()
                    .map(|(k, l)| dualsph_io::TableColumn {
                        name: l.clone(),
                        labels: vec![l.clone()],
                        values: (0..t.len()).map(|r| c.row(r)[k]).collect(),
                    })
            })
            .collect(),
    };
    let groups: Vec<(String, Vec<String>)> = t
        .columns
        .iter()
        .map(|c| (c.name.clone(), c.labels.clone()))
        .collect();
    assert_eq!(flat.grouped(&groups), t);
}

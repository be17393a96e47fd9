//! Tests of the output directory, the CSV round trips and the VTK files.

use crate::test_particles::{Particle, particles_of, table_of};
use crate::vtk_tests::{check_vtp, check_xml_balanced};
use crate::*;

/// The particles of the file at `path` ([`read_particles`]).
fn read_back(path: &std::path::Path) -> Vec<Particle> {
    particles_of(&read_particles(path).unwrap())
}

fn particles(n: usize) -> Vec<Particle> {
    let tricky = [
        0.1,
        1.0 / 3.0,
        -0.0,
        1e-300,
        5e-324,
        f64::MIN_POSITIVE,
        f64::MAX,
        -1.2345678901234567e17,
        std::f64::consts::PI,
        1e-5,
        1e16 - 2.0, // largest value printed without exponent
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    (0..n)
        .map(|i| {
            let x = |k: usize| tricky[(i * 11 + k) % tricky.len()] * (1.0 + i as f64);
            Particle {
                id: if i == 0 { u64::MAX } else { i as u64 * 7 },
                pos: [x(0), x(1), x(2)],
                vel: [x(3), x(4), x(5)],
                mass: x(6),
                rho: x(7),
                p: x(8),
                e: x(9),
                h: x(10),
            }
        })
        .collect()
}

fn bits(p: &Particle) -> Vec<u64> {
    let mut v = vec![p.id];
    v.extend(p.pos.iter().chain(&p.vel).map(|x| x.to_bits()));
    v.extend([p.mass, p.rho, p.p, p.e, p.h].map(f64::to_bits));
    v
}

fn row(step: u64, extra: Vec<Real>) -> DiagnosticsRow {
    DiagnosticsRow {
        t: step as f64 * 0.1,
        step,
        dt: 0.1,
        n: 100,
        mass: 1.0,
        p: [1e-17, -2.5, 0.0],
        lz: 3.25,
        e_kin: 0.5,
        e_int: 2.0 / 3.0,
        e_pot: -1.0,
        e_tot: 0.5 + 2.0 / 3.0 - 1.0,
        extra,
    }
}

#[test]
fn particles_round_trip_bitwise() {
    let tmp = tempfile::tempdir().unwrap();
    let out = OutputDir::create(tmp.path(), vec![], OutputOptions::default()).unwrap();
    let ps = particles(40);
    out.write_final(&table_of(&ps)).unwrap();
    let path = tmp.path().join(FINAL_FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("id,x,y,z,vx,vy,vz,m,rho,p,e,h\n"));
    let back = read_back(&path);
    assert_eq!(back.len(), ps.len());
    for (a, b) in ps.iter().zip(&back) {
        assert_eq!(bits(a), bits(b), "{a:?} vs {b:?}");
    }
    // NaN survives as NaN.
    let nan = Particle {
        rho: f64::NAN,
        ..Particle::default()
    };
    out.write_final(&table_of(&[nan])).unwrap();
    assert!(read_back(&path)[0].rho.is_nan());
}

#[test]
fn empty_particle_set_round_trips() {
    let tmp = tempfile::tempdir().unwrap();
    let mut out = OutputDir::create(tmp.path(), vec![], OutputOptions::default()).unwrap();
    out.write_snapshot(0, 0.0, &table_of(&[])).unwrap();
    let back = read_back(&tmp.path().join("particles_000000.csv"));
    assert!(back.is_empty());
    check_vtp(&tmp.path().join("particles_000000.vtp"), 0);
}

#[test]
fn particle_csv_with_a_missing_column_or_a_bad_value_is_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("bad.csv");
    std::fs::write(&path, "id,x,y\n1,2,3\n").unwrap();
    let table = read_particles(&path).unwrap();
    let err = table.require(&[POSITION, MASS]).unwrap_err();
    // the file's own labels are not quoted
    assert!(!err.contains("x, y"), "{err}");
    assert!(
        err.contains("no column `") && err.contains("the file's 2 column(s)"),
        "{err}"
    );
    std::fs::write(
        &path,
        "id,x,y,z,vx,vy,vz,m,rho,p,e,h\n1,2,3,4,5,6,7,8,9,10,11,zz\n",
    )
    .unwrap();
    let err = read_particles(&path).unwrap_err();
    assert!(err.to_string().contains("line 2"), "{err}");
    assert!(err.to_string().contains("`h`"), "{err}");
    let missing = tmp.path().join("missing.csv");
    let err = read_particles(&missing).unwrap_err();
    assert_eq!(err.path(), missing);
}

#[test]
fn diagnostics_header_and_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let extra = vec!["l1_err".to_string(), "max_h".to_string()];
    let mut out = OutputDir::create(tmp.path(), extra.clone(), OutputOptions::default()).unwrap();
    let path = tmp.path().join(DIAGNOSTICS_FILE);
    let (header, rows) = read_diagnostics_csv(&path).unwrap();
    assert_eq!(
        header.join(","),
        "t,step,dt,n,mass,px,py,pz,lz,e_kin,e_int,e_pot,e_tot,l1_err,max_h"
    );
    assert!(rows.is_empty());

    let r: Vec<_> = (0..5).map(|s| row(s, vec![1e-9 * s as f64, 0.3])).collect();
    for x in &r {
        out.push_diagnostics(x.clone()).unwrap();
    }
    let (header2, rows) = read_diagnostics_csv(&path).unwrap();
    assert_eq!(header2, header);
    assert_eq!(rows.len(), 5);
    assert_eq!(out.diagnostics_len(), 5);
    for (x, got) in r.iter().zip(&rows) {
        let want = [
            x.t,
            x.step as f64,
            x.dt,
            x.n as f64,
            x.mass,
            x.p[0],
            x.p[1],
            x.p[2],
            x.lz,
            x.e_kin,
            x.e_int,
            x.e_pot,
            x.e_tot,
            x.extra[0],
            x.extra[1],
        ];
        assert_eq!(
            want.map(f64::to_bits).to_vec(),
            got.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }
    // Integer columns are written as integers.
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.lines().nth(2).unwrap().starts_with("0.1,1,0.1,100,1,"),
        "{text}"
    );

    // Wrong number of extra values: error naming the file, nothing changed.
    let err = out.push_diagnostics(row(5, vec![1.0])).unwrap_err();
    assert!(matches!(err, OutputError::Invalid { .. }));
    assert_eq!(err.path(), path);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);

    // Re-pushing an earlier step supersedes the later rows.
    out.push_diagnostics(row(3, vec![7.0, 8.0])).unwrap();
    let (_, rows) = read_diagnostics_csv(&path).unwrap();
    assert_eq!(
        rows.iter().map(|r| r[1]).collect::<Vec<_>>(),
        [0.0, 1.0, 2.0, 3.0]
    );
    assert_eq!(rows[3][13], 7.0);
}

#[test]
fn invalid_extra_column_names_are_rejected() {
    let tmp = tempfile::tempdir().unwrap();
    for bad in [
        vec![""],
        vec!["a,b"],
        vec!["x", "x"],
        vec!["e_tot"],
        vec!["q\n"],
    ] {
        let cols = bad.iter().map(|s| s.to_string()).collect();
        let err = OutputDir::create(tmp.path(), cols, OutputOptions::default()).unwrap_err();
        assert!(matches!(err, OutputError::Invalid { .. }), "{bad:?}: {err}");
    }
}

#[test]
fn snapshot_index_and_pvd() {
    let tmp = tempfile::tempdir().unwrap();
    let mut out = OutputDir::create(tmp.path(), vec![], OutputOptions::default()).unwrap();
    let ps = particles(5);
    out.write_snapshot(0, 0.0, &table_of(&ps)).unwrap();
    out.write_snapshot(10, 0.25, &table_of(&ps[..3])).unwrap();
    out.write_snapshot(1_234_567, 1e-7, &table_of(&ps[..1]))
        .unwrap();
    out.write_snapshot(10, 0.5, &table_of(&ps[..4])).unwrap(); // replaces step 10

    let index = std::fs::read_to_string(tmp.path().join(SNAPSHOT_INDEX_FILE)).unwrap();
    assert_eq!(
        index,
        "step,t,file\n0,0,particles_000000.csv\n10,0.5,particles_000010.csv\n\
         1234567,1e-7,particles_1234567.csv\n"
    );
    assert_eq!(out.snapshots().len(), 3);
    assert_eq!(out.snapshots()[2].vtp_file(), "particles_1234567.vtp");

    let pvd = std::fs::read_to_string(tmp.path().join(PVD_FILE)).unwrap();
    check_xml_balanced(&pvd);
    assert!(pvd.contains("<VTKFile type=\"Collection\""));
    let sets: Vec<&str> = pvd.lines().filter(|l| l.contains("<DataSet")).collect();
    assert_eq!(sets.len(), 3, "{pvd}");
    assert!(
        sets[0].contains("timestep=\"0\"") && sets[0].contains("file=\"particles_000000.vtp\"")
    );
    assert!(
        sets[1].contains("timestep=\"0.5\"") && sets[1].contains("file=\"particles_000010.vtp\"")
    );
    assert!(
        sets[2].contains("timestep=\"1e-7\"") && sets[2].contains("file=\"particles_1234567.vtp\"")
    );

    for (e, n) in out.snapshots().iter().zip([5, 4, 1]) {
        let back = read_back(&tmp.path().join(&e.file));
        assert_eq!(back.len(), n);
        check_vtp(&tmp.path().join(e.vtp_file()), n);
    }
}

#[test]
fn unwritable_directory_gives_error_naming_path() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("not_a_dir");
    std::fs::write(&file, b"").unwrap();
    let dir = file.join("out");
    let err = OutputDir::create(&dir, vec![], OutputOptions::default()).unwrap_err();
    assert!(matches!(err, OutputError::Io { .. }), "{err}");
    assert!(err.to_string().contains(&*dir.to_string_lossy()), "{err}");
    assert_eq!(err.path(), dir);
}

#[test]
fn reopen_truncates_after_up_to_step() {
    let tmp = tempfile::tempdir().unwrap();
    let extra = vec!["err".to_string()];
    let mut out = OutputDir::create(tmp.path(), extra.clone(), OutputOptions::default()).unwrap();
    let ps = particles(3);
    for s in 0..10 {
        out.push_diagnostics(row(s, vec![s as f64])).unwrap();
        if s % 3 == 0 {
            out.write_snapshot(s, s as f64 * 0.1, &table_of(&ps))
                .unwrap();
        }
    }
    drop(out);

    let mut out =
        OutputDir::reopen(tmp.path(), extra.clone(), 4, OutputOptions::default()).unwrap();
    assert_eq!(out.diagnostics_len(), 5);
    let steps: Vec<u64> = out.snapshots().iter().map(|e| e.step).collect();
    assert_eq!(steps, [0, 3]);
    // Files are rewritten immediately.
    let (_, rows) = read_diagnostics_csv(&tmp.path().join(DIAGNOSTICS_FILE)).unwrap();
    assert_eq!(
        rows.iter().map(|r| r[1]).collect::<Vec<_>>(),
        [0.0, 1.0, 2.0, 3.0, 4.0]
    );
    let pvd = std::fs::read_to_string(tmp.path().join(PVD_FILE)).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 2);
    assert!(!pvd.contains("particles_000006"));

    // Continue the run: new rows and snapshots append after the kept ones.
    out.push_diagnostics(row(5, vec![50.0])).unwrap();
    out.write_snapshot(6, 0.6, &table_of(&ps)).unwrap();
    let (_, rows) = read_diagnostics_csv(&tmp.path().join(DIAGNOSTICS_FILE)).unwrap();
    assert_eq!(rows.len(), 6);
    assert_eq!(rows[5][13], 50.0);
    assert_eq!(
        rows[4],
        [
            0.4,
            4.0,
            0.1,
            100.0,
            1.0,
            1e-17,
            -2.5,
            0.0,
            3.25,
            0.5,
            2.0 / 3.0,
            -1.0,
            0.5 + 2.0 / 3.0 - 1.0,
            4.0
        ]
    );
    let index = std::fs::read_to_string(tmp.path().join(SNAPSHOT_INDEX_FILE)).unwrap();
    assert_eq!(index.lines().count(), 4);

    // A different extra column set does not match the existing file.
    let err = OutputDir::reopen(tmp.path(), vec![], 4, OutputOptions::default()).unwrap_err();
    assert!(matches!(err, OutputError::Parse { .. }), "{err}");

    // Reopening a fresh directory works and starts empty.
    let fresh = tmp.path().join("fresh");
    let out = OutputDir::reopen(&fresh, vec![], 100, OutputOptions::default()).unwrap();
    assert_eq!(out.diagnostics_len(), 0);
    assert!(out.snapshots().is_empty());
    assert_eq!(out.dir(), fresh);
}

#[test]
fn output_files_leave_no_temporaries() {
    let tmp = tempfile::tempdir().unwrap();
    let mut out = OutputDir::create(tmp.path(), vec![], OutputOptions::default()).unwrap();
    out.push_diagnostics(row(0, vec![])).unwrap();
    out.write_snapshot(0, 0.0, &table_of(&particles(2)))
        .unwrap();
    out.write_final(&table_of(&particles(2))).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "diagnostics.csv",
            "final.csv",
            "particles.pvd",
            "particles_000000.csv",
            "particles_000000.vtp",
            "snapshots.csv"
        ]
    );
}

#[test]
fn a_table_of_any_columns_is_written_and_read_back_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    let mut out = OutputDir::create(tmp.path(), vec![], OutputOptions::default()).unwrap();
    let ps = particles(5);
    let mut table = table_of(&ps);
    // a scene without EOS or energy equation, and a plugin's 2×2 matrix column
    table
        .columns
        .retain(|c| c.name != "pressure" && c.name != "internal_energy");
    table.columns.push(TableColumn {
        name: "stress".into(),
        labels: ["s_xx", "s_xy", "s_yx", "s_yy"].map(String::from).into(),
        values: (0..20).map(|k| k as f64 * 0.25).collect(),
    });
    out.write_snapshot(3, 0.5, &table).unwrap();
    let csv = tmp.path().join("particles_000003.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("id,x,y,z,vx,vy,vz,m,rho,h,s_xx,s_xy,s_yx,s_yy\n"),
        "{text}"
    );
    let back = read_back(&csv);
    for (a, b) in ps.iter().zip(&back) {
        assert_eq!(
            (a.id, a.rho.to_bits(), b.p, b.e),
            (b.id, b.rho.to_bits(), 0.0, 0.0)
        );
    }
    let (header, rows) = read_diagnostics_csv(&csv).unwrap();
    let s_yx = header.iter().position(|h| h == "s_yx").unwrap();
    assert_eq!(rows[4][s_yx], 18.0 * 0.25);
    let vtp = std::fs::read(tmp.path().join("particles_000003.vtp")).unwrap();
    let vtp = String::from_utf8_lossy(&vtp);
    check_xml_balanced(&format!(
        "{}</VTKFile>",
        &vtp[..vtp.find("<AppendedData").unwrap()]
    ));
    assert!(
        vtp.contains("Name=\"stress\" NumberOfComponents=\"4\""),
        "{vtp}"
    );
    assert!(!vtp.contains("Name=\"pressure\""));
    // a column whose values do not fit the rows is refused, and nothing is written
    table.columns[0].values.pop();
    let err = out.write_final(&table).unwrap_err();
    assert!(matches!(err, OutputError::Invalid { .. }), "{err}");
    assert!(!tmp.path().join(FINAL_FILE).exists());
}

#[test]
fn snapshots_are_written_in_the_chosen_formats_only() {
    let names = |dir: &std::path::Path| {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let table = table_of(&particles(3));
    let tmp = tempfile::tempdir().unwrap();
    let (csv, vtk, none) = (
        tmp.path().join("csv"),
        tmp.path().join("vtk"),
        tmp.path().join("none"),
    );
    let only = |csv, vtk| OutputOptions {
        csv,
        vtk,
        encoding: VtkEncoding::Compressed,
    };
    let mut out = OutputDir::create(&csv, vec![], only(true, false)).unwrap();
    out.write_snapshot(4, 0.5, &table).unwrap();
    out.write_final(&table).unwrap();
    assert_eq!(
        names(&csv),
        [
            "diagnostics.csv",
            "final.csv",
            "particles_000004.csv",
            "snapshots.csv"
        ]
    );
    let mut out = OutputDir::create(&vtk, vec![], only(false, true)).unwrap();
    out.write_snapshot(4, 0.5, &table).unwrap();
    assert_eq!(
        names(&vtk),
        [
            "diagnostics.csv",
            "particles.pvd",
            "particles_000004.vtp",
            "snapshots.csv"
        ]
    );
    assert_eq!(out.snapshots()[0].file, "particles_000004.vtp");
    assert_eq!(out.snapshots()[0].vtp_file(), "particles_000004.vtp");
    check_vtp(&vtk.join("particles_000004.vtp"), 3);
    let pvd = std::fs::read_to_string(vtk.join(PVD_FILE)).unwrap();
    assert!(pvd.contains("file=\"particles_000004.vtp\""), "{pvd}");
    let out = OutputDir::reopen(&vtk, vec![], 10, only(false, true)).unwrap();
    assert_eq!(out.snapshots().len(), 1);
    let mut out = OutputDir::create(&none, vec![], only(false, false)).unwrap();
    out.write_snapshot(4, 0.5, &table).unwrap();
    assert!(out.snapshots().is_empty());
    assert_eq!(names(&none), ["diagnostics.csv", "snapshots.csv"]);
}

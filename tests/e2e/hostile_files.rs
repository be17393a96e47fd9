//! Files that are not what a scene says they are: a device, a pipe, a sparse file of a
//! terabyte, a directory, someone else's text outside the scene's directory. `dualsph check`,
//! run under `ulimit -v` of 4 GiB, refuses each within seconds, naming the field (or the scene
//! file), never printing a byte of the file, never aborting.

use crate::limited;

use std::path::{Path, PathBuf};
use std::process::Command;

/// What no message may contain: it is only in the foreign files.
const SECRET: &str = "SECRET-7f3a";

/// Virtual memory the command may use (KiB, for `ulimit -v`).
const MEMORY_KIB: u64 = 4 << 20;

/// `dualsph check SCENE` under the memory limit, killed if it takes over 60 s:
/// (exit code, standard error).
fn check(scene: &Path) -> (Option<i32>, String) {
    limited::dualsph_limited(&["check".into(), scene.into()], MEMORY_KIB)
}

fn scene_2d(generator: &str) -> String {
    format!(
        "Scene(name: \"hostile\", dimension: 2, domain: (min: [-1.0, -1.0], max: [2.0, 2.0]),
         kernel: CubicSpline,
         particles: [{generator}],
         plugins: [TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0), PressureForce()],
         integrator: (dt: Fixed(1e-4)), end_time: 0.001)"
    )
}

fn scene_3d(generator: &str) -> String {
    scene_2d(generator)
        .replace("dimension: 2", "dimension: 3")
        .replace("[-1.0, -1.0]", "[-1.0, -1.0, -1.0]")
        .replace("[2.0, 2.0]", "[2.0, 2.0, 2.0]")
}

fn polygon(file: &str) -> String {
    scene_2d(&format!(
        "Shape(shape: PolygonFile(file: \"{file}\"), spacing: 0.1, density: 1000.0, h_factor: 2.0)"
    ))
}

fn particles(file: &str) -> String {
    scene_2d(&format!("File(path: \"{file}\")"))
}

fn stl(file: &str) -> String {
    scene_3d(&format!(
        "Shape(shape: Stl(file: \"{file}\"), spacing: 0.1, density: 1000.0, h_factor: 2.0)"
    ))
}

/// The foreign files beside the scene's directory, and a FIFO and a sparse file in it.
fn fixtures(root: &Path) -> PathBuf {
    let dir = root.join("scenes");
    std::fs::create_dir(&dir).unwrap();
    let lines = format!("{SECRET}:x:0:0:root:/root:/bin/sh\n{SECRET} 1.0 2.0\n1.0, {SECRET}\n");
    std::fs::write(root.join("passwd"), &lines).unwrap();
    std::fs::write(
        root.join("foreign.csv"),
        format!("{SECRET},x,y\n1,{SECRET},2\n"),
    )
    .unwrap();
    std::fs::write(root.join("header.csv"), format!("id,x,y\n1,{SECRET},2\n")).unwrap();
    std::fs::write(
        root.join("foreign.vtp"),
        format!("<VTKFile><{SECRET}>{SECRET}</{SECRET}>"),
    )
    .unwrap();
    std::fs::write(
        root.join("foreign.stl"),
        format!("solid {SECRET}\nfacet {SECRET}\n"),
    )
    .unwrap();
    std::fs::File::create(dir.join("sparse"))
        .unwrap()
        .set_len(1 << 40)
        .unwrap();
    let fifo = Command::new("mkfifo").arg(dir.join("fifo")).status();
    assert!(fifo.is_ok_and(|s| s.success()), "mkfifo");
    dir
}

#[test]
fn files_that_are_not_what_the_scene_says_are_refused_unread_and_unquoted() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = fixtures(tmp.path());
    let shape = "particles[0].shape.file";
    let file = "particles[0].path";
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "device polygon",
            polygon("/dev/zero"),
            shape,
            "not a regular file",
        ),
        ("pipe polygon", polygon("fifo"), shape, "not a regular file"),
        (
            "sparse polygon",
            polygon("sparse"),
            shape,
            "more than the 2 GiB",
        ),
        ("directory polygon", polygon("."), shape, "directory"),
        (
            "foreign polygon",
            polygon("../passwd"),
            shape,
            "expected a row of two",
        ),
        (
            "foreign particles",
            particles("../foreign.csv"),
            file,
            "cannot read particles",
        ),
        (
            "foreign values",
            particles("../header.csv"),
            file,
            "not a number",
        ),
        (
            "device particles",
            particles("/dev/zero"),
            file,
            "not a regular file",
        ),
        (
            "sparse particles",
            particles("sparse"),
            file,
            "more than the 2 GiB",
        ),
        (
            "foreign vtp",
            particles("../foreign.vtp"),
            file,
            "cannot read particles",
        ),
        ("pipe stl", stl("fifo"), shape, "not a regular file"),
        (
            "foreign stl",
            stl("../foreign.stl"),
            shape,
            "cannot read STL file",
        ),
    ];
    for (what, text, field, says) in cases {
        let scene = dir.join(format!("{}.ron", what.replace(' ', "_")));
        std::fs::write(&scene, text).unwrap();
        let (code, err) = check(&scene);
        assert_eq!(code, Some(2), "{what}: {err}");
        assert!(err.contains(field) && err.contains(says), "{what}: {err}");
        assert!(
            !err.contains(SECRET),
            "{what}: the message quotes the file: {err}"
        );
        assert!(
            !err.contains("panicked") && err.lines().count() == 1,
            "{what}: {err}"
        );
    }
}

#[test]
fn a_scene_path_that_is_not_a_scene_file_is_refused_unread() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = fixtures(tmp.path());
    for (path, says) in [
        (PathBuf::from("/dev/zero"), "not a regular file"),
        (dir.join("fifo"), "not a regular file"),
        (dir.join("sparse"), "more than the 16 MiB"),
        (dir.clone(), "directory"),
    ] {
        let (code, err) = check(&path);
        assert_eq!(code, Some(4), "{}: {err}", path.display());
        assert!(err.contains(says), "{}: {err}", path.display());
    }
}

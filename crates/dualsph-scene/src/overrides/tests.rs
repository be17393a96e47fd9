use super::*;

const SCENE: &str = "Scene(
    name: \"t\", // a comment (with a parenthesis
    particles: [
        Block(min: [0.0], max: [1.0], spacing: 0.1),
        Block(min: [2.0], max: [3.0], spacing: 0.1,),
    ],
    plugins: [TaitEos(rho0: 1000.0, c0: 20.0), PressureForce, Gravity(), Probes(probes: [])],
    integrator: (dt: Adaptive(courant: 0.2)),
    end_time: 1.0,
)";

fn set(overrides: &[&str]) -> Result<String, ApplyError> {
    let o: Vec<Override> = overrides.iter().map(|s| s.parse().unwrap()).collect();
    apply(SCENE, &o).map(|e| e.text)
}

fn set_err(one: &str) -> String {
    match set(&[one]) {
        Err(ApplyError::Set(0, m)) => m,
        other => panic!("{one}: {other:?}"),
    }
}

#[test]
fn a_value_is_replaced_where_it_is_written_and_nothing_else_changes() {
    let t = set(&[
        "particles[1].spacing=0.05",
        "TaitEos.c0=60",
        "integrator.dt.courant=0.1",
    ]);
    let expected = SCENE
        .replace("spacing: 0.1,)", "spacing: 0.05,)")
        .replace("c0: 20.0", "c0: 60")
        .replace("courant: 0.2", "courant: 0.1");
    assert_eq!(t.unwrap(), expected);
}

#[test]
fn a_field_at_its_default_is_added() {
    let t = set(&["max_steps=10", "PressureForce.x=1", "Gravity.g=[0.0]"]);
    let t = t.unwrap();
    assert!(t.contains("end_time: 1.0,\n max_steps: 10)"), "{t}");
    assert!(t.contains("PressureForce(x: 1)"), "{t}");
    assert!(t.contains("Gravity(g: [0.0])"), "{t}");
    // a trailing comma is kept, not doubled
    let t = set(&["particles[1].velocity=Uniform([1.0])"]).unwrap();
    assert!(t.contains("spacing: 0.1, velocity: Uniform([1.0]))"), "{t}");
}

#[test]
fn a_path_that_names_nothing_says_why() {
    assert!(set_err("Block.spacing=1").contains("particles[0], particles[1]"));
    assert!(set_err("particles[2].spacing=1").contains("has 2 members"));
    assert!(set_err("end_time.x=1").contains("no field or member `x`"));
    assert!(set_err("output.snapshot_dt=1").contains("set the whole `output`"));
    assert!(set_err("Viscosity.alpha=1").contains("no field or list member `Viscosity`"));
}

#[test]
fn bad_arguments_are_refused_before_any_scene_is_read() {
    for bad in [
        "c0",
        "=1",
        "a..b=1",
        "a[x]=1",
        "a[1=1",
        "a=",
        "a=(1",
        "a=1 2",
        "a=1, b: 2",
    ] {
        assert!(bad.parse::<Override>().is_err(), "{bad}");
    }
    let o: Override = "plugins[0].c0 = 60 ".parse().unwrap();
    assert_eq!(o.value, "60");
}

#[test]
fn positions_in_the_edited_text_trace_back_to_the_file_or_the_override() {
    let o: Vec<Override> = ["TaitEos.c0=123456", "max_steps=7"]
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    let e = apply(SCENE, &o).unwrap();
    let in_value = e.text.find("123456").unwrap() + 2;
    assert_eq!(e.origin(in_value), Origin::Set(0));
    let after = e.text.find("integrator").unwrap();
    assert_eq!(
        e.origin(after),
        Origin::File(SCENE.find("integrator").unwrap())
    );
    assert_eq!(e.origin(e.text.find("max_steps").unwrap()), Origin::Set(1));
    assert_eq!(e.origin(0), Origin::File(0));
    let (l, c) = line_col(SCENE, SCENE.find("integrator").unwrap());
    assert_eq!((l, c), (8, 5));
    assert_eq!(offset_of(SCENE, l, c), SCENE.find("integrator").unwrap());
}

#[test]
fn a_broken_scene_is_left_to_the_scene_parser() {
    let o: Vec<Override> = vec!["end_time=2".parse().unwrap()];
    assert!(matches!(
        apply("Scene(a: (1", &o),
        Err(ApplyError::Text(..))
    ));
}

#[test]
fn a_value_is_appended_to_a_list() {
    let t = set(&["plugins[+]=Viscosity(alpha: 0.02)"]).unwrap();
    assert!(
        t.contains("Probes(probes: []), Viscosity(alpha: 0.02)]"),
        "{t}"
    );
    // after a trailing comma, into an empty list, twice, and into a list the scene leaves out
    let t = set(&["particles[+]=Block(min: [4.0], max: [5.0], spacing: 0.1)"]).unwrap();
    assert!(
        t.contains("spacing: 0.1,),\n    Block(min: [4.0], max: [5.0], spacing: 0.1), ]"),
        "{t}"
    );
    let t = set(&["Probes.probes[+]=A", "Probes.probes[+]=B"]).unwrap();
    assert!(t.contains("Probes(probes: [A, B])"), "{t}");
    let t = set(&["bodies[+]=(name: \"w\")"]).unwrap();
    assert!(
        t.contains("end_time: 1.0,\n bodies: [(name: \"w\")])"),
        "{t}"
    );
}

#[test]
fn an_append_that_cannot_be_made_says_why() {
    assert!(set_err("end_time[+]=1").contains("`end_time` is not a list"));
    assert!(set_err("TaitEos[+]=1").contains("`TaitEos` is not a list"));
    for bad in ["plugins[+].c0=1", "plugins[+][0]=1", "plugins[+=1"] {
        let e = bad.parse::<Override>().unwrap_err();
        assert!(e.contains("[+]") || e.contains("[index]"), "{bad}: {e}");
    }
}

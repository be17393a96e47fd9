//! The order of the systems inside a [`crate::sim::StepSet`]: the order they were added in,
//! changed only as far as their `after` / `before` constraints require
//! ([`crate::sim::SystemOrder`]). A constraint names a *group* of systems by its type (a
//! [`SystemGroup`]: the equations of state, the driving of bodies, the force sweep), which a
//! system joins with [`crate::sim::SystemOrder::in_group`]; a group no system of the set
//! joins is no constraint (its plugin is not in the scene), and a user's system that joins a
//! group is ordered with the built-in ones without any edit elsewhere. A cycle is an error
//! that names the systems and the plugins that added them.

use std::any::TypeId;

/// A group of systems that other systems are placed against by type: a plugin declares one as
/// a unit struct with `impl SystemGroup for MyGroup {}`, its systems join it
/// ([`crate::sim::SystemOrder::in_group`]) and others run after or before it
/// ([`crate::sim::SystemOrder::after`]). The same type can be the marker resource that says
/// the group's provider is in the scene ([`crate::sim::Sim::enable`]).
pub trait SystemGroup: 'static {}

/// What the sort needs of one system.
#[derive(Clone, Debug, Default)]
pub struct Placement {
    /// The label (its name is the part before the first blank).
    pub label: String,
    /// The plugin that added it (`core` for the engine's own).
    pub plugin: String,
    /// The groups it belongs to.
    pub groups: Vec<TypeId>,
    /// The groups it runs after.
    pub after: Vec<TypeId>,
    /// The groups it runs before.
    pub before: Vec<TypeId>,
}

impl Placement {
    /// The system's name: its label up to the first blank.
    pub fn name(&self) -> &str {
        self.label.split_whitespace().next().unwrap_or("")
    }

    fn in_any(&self, groups: &[TypeId]) -> bool {
        groups.iter().any(|g| self.groups.contains(g))
    }

    fn describe(&self) -> String {
        format!("`{}` ({})", self.name(), self.plugin)
    }
}

/// The indices of `systems` (one set) in run order: insertion order where no constraint
/// decides (a stable topological sort); the error names a cycle.
pub fn order(systems: &[Placement]) -> Result<Vec<usize>, String> {
    let n = systems.len();
    // edge a → b: a runs before b
    let mut preds: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (b, s) in systems.iter().enumerate() {
        for (a, t) in systems.iter().enumerate() {
            if a == b {
                continue;
            }
            let b_after_a = t.in_any(&s.after);
            let a_before_b = s.in_any(&t.before);
            if b_after_a || a_before_b {
                preds[b].push(a);
            }
        }
    }
    let mut done = vec![false; n];
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let next = (0..n).find(|&k| !done[k] && preds[k].iter().all(|&p| done[p]));
        let Some(k) = next else {
            return Err(cycle(systems, &preds, &done));
        };
        done[k] = true;
        out.push(k);
    }
    Ok(out)
}

/// The message for a cycle among the systems not yet placed.
fn cycle(systems: &[Placement], preds: &[Vec<usize>], done: &[bool]) -> String {
    // walk back along unplaced predecessors until a system repeats
    let mut path = vec![(0..systems.len()).find(|&k| !done[k]).unwrap_or(0)];
    loop {
        let last = *path.last().unwrap_or(&0);
        let Some(&p) = preds[last].iter().find(|&&p| !done[p]) else {
            break;
        };
        if let Some(at) = path.iter().position(|&k| k == p) {
            path.drain(..at);
            break;
        }
        path.push(p);
    }
    let names: Vec<String> = path.iter().rev().map(|&k| systems[k].describe()).collect();
    format!(
        "the systems' order constraints contradict each other: {} must each run before the next, and the last before the first",
        names.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Sweep;
    struct Continuity;
    struct Elsewhere;

    fn group<G: 'static>() -> TypeId {
        TypeId::of::<G>()
    }

    fn sys(
        label: &str,
        plugin: &str,
        groups: &[TypeId],
        after: &[TypeId],
        before: &[TypeId],
    ) -> Placement {
        Placement {
            label: label.into(),
            plugin: plugin.into(),
            groups: groups.to_vec(),
            after: after.to_vec(),
            before: before.to_vec(),
        }
    }

    #[test]
    fn insertion_order_unless_a_constraint_says_otherwise() {
        let (sweep, cont, elsewhere) = (
            group::<Sweep>(),
            group::<Continuity>(),
            group::<Elsewhere>(),
        );
        let s = [
            sys(
                "density_diffusion (δ-SPH)",
                "DensityDiffusion",
                &[],
                &[sweep, cont],
                &[],
            ),
            sys("pair_sweep (support)", "core", &[sweep], &[], &[]),
            sys(
                "continuity_pairwise (Eq. 4.9)",
                "ContinuityDensity",
                &[cont],
                &[],
                &[],
            ),
            sys("pair_balance", "core", &[], &[], &[sweep]),
            sys("unrelated", "X", &[], &[elsewhere], &[]),
        ];
        let o = order(&s).unwrap();
        let at = |k: usize| o.iter().position(|&x| x == k).unwrap();
        assert!(
            at(0) > at(1) && at(0) > at(2),
            "diffusion after sweep and continuity: {o:?}"
        );
        assert!(at(3) < at(1), "balance before the sweep: {o:?}");
        assert_eq!(
            o,
            vec![2, 3, 1, 0, 4],
            "the first system whose predecessors have run"
        );
    }

    #[test]
    fn a_cycle_names_both_plugins() {
        struct A;
        struct B;
        let (a, b) = (group::<A>(), group::<B>());
        let s = [
            sys("a_sys", "PluginA", &[a], &[b], &[]),
            sys("b_sys", "PluginB", &[b], &[a], &[]),
            sys("c_sys", "core", &[], &[], &[]),
        ];
        let e = order(&s).unwrap_err();
        assert!(
            e.contains("`a_sys` (PluginA)") && e.contains("`b_sys` (PluginB)"),
            "{e}"
        );
        assert!(!e.contains("c_sys"), "{e}");
    }
}

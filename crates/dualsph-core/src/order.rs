//! The order of the systems inside a [`crate::sim::StepSet`]: the order they were added in,
//! changed only as far as their `after` / `before` constraints require
//! ([`crate::sim::SystemOrder`]). A constraint names a system by its name — its label up to
//! the first blank (`density_diffusion`), or a prefix of it that ends at an underscore
//! (`continuity` names `continuity_pairwise`) — or by the plugin that added it (`TaitEos`);
//! a name that matches nothing is no constraint (the other plugin is not in the scene). A
//! cycle is an error that names the systems and the plugins that added them.

/// What the sort needs of one system.
#[derive(Clone, Debug, Default)]
pub struct Placement {
    /// The label (its name is the part before the first blank).
    pub label: String,
    /// The plugin that added it (`core` for the engine's own).
    pub plugin: String,
    /// Names it runs after.
    pub after: Vec<String>,
    /// Names it runs before.
    pub before: Vec<String>,
}

impl Placement {
    /// The system's name: its label up to the first blank.
    pub fn name(&self) -> &str {
        self.label.split_whitespace().next().unwrap_or("")
    }

    /// Whether `name` names this system (see the module docs).
    pub fn answers_to(&self, name: &str) -> bool {
        let own = self.name();
        own == name
            || self.plugin == name
            || own
                .strip_prefix(name)
                .is_some_and(|rest| rest.starts_with('_'))
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
            let b_after_a = s.after.iter().any(|name| t.answers_to(name));
            let a_before_b = t.before.iter().any(|name| s.answers_to(name));
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

    fn sys(label: &str, plugin: &str, after: &[&str], before: &[&str]) -> Placement {
        Placement {
            label: label.into(),
            plugin: plugin.into(),
            after: after.iter().map(|s| s.to_string()).collect(),
            before: before.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn insertion_order_unless_a_constraint_says_otherwise() {
        let s = [
            sys(
                "density_diffusion (δ-SPH)",
                "DensityDiffusion",
                &["pair_sweep", "continuity"],
                &[],
            ),
            sys("pair_sweep (support)", "core", &[], &[]),
            sys(
                "continuity_pairwise (Eq. 4.9)",
                "ContinuityDensity",
                &[],
                &[],
            ),
            sys("pair_balance", "core", &[], &["pair_sweep"]),
            sys("unrelated", "X", &["NotInTheScene"], &[]),
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
        assert!(s[2].answers_to("continuity") && s[2].answers_to("ContinuityDensity"));
        assert!(!s[2].answers_to("contin"));
    }

    #[test]
    fn a_cycle_names_both_plugins() {
        let s = [
            sys("a_sys", "PluginA", &["b_sys"], &[]),
            sys("b_sys", "PluginB", &["PluginA"], &[]),
            sys("c_sys", "core", &[], &[]),
        ];
        let e = order(&s).unwrap_err();
        assert!(
            e.contains("`a_sys` (PluginA)") && e.contains("`b_sys` (PluginB)"),
            "{e}"
        );
        assert!(!e.contains("c_sys"), "{e}");
    }
}

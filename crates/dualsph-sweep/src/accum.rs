//! Accumulators: the per-particle sums a pair sweep forms and writes into registered columns.
//!
//! A term declares each sum it writes when it is bound ([`Binder`]): the column (any
//! [`ColumnValue`]: scalar, vector or matrix), how the pair's contribution reaches the
//! neighbour ([`Reaction`]) and how the finished sum becomes the column's value ([`Finish`]).
//! Terms that write the same column share its sum. The sweep gives each declaration a handle
//! ([`Acc`]) into its channels: one value per pair for the owner and, with
//! [`Reaction::Separate`], one for the neighbour. After the sweep every particle's column is
//! set to `finish(Σ)`: the sweep owns the column for the step.

use bevy_ecs::component::Mutable;
use bevy_ecs::prelude::*;
use dualsph_core::columns::{ColumnValue, Shape, take_vector};
use dualsph_core::components::{Acceleration, Mass};
use dualsph_core::kernels::Kernel;
use dualsph_core::math::{Real, Vector};
use dualsph_core::store::{ParticleData, single_table};
use rayon::prelude::*;
use std::any::TypeId;

/// Owner channels a sweep can sum (the per-particle sums of all its accumulators).
pub const MAX_OWNER_CHANNELS: usize = 16;
/// Neighbour channels a sweep can carry ([`Reaction::Separate`] accumulators).
pub const MAX_NEIGHBOUR_CHANNELS: usize = 8;

/// How a pair's contribution to the owner i reaches the neighbour j.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reaction {
    /// j receives the opposite of i's contribution (a force: linear momentum is exchanged
    /// exactly, whatever the h field).
    Opposite,
    /// j receives what the term writes for it with [`crate::pair::Out::react`] (energy, mass
    /// exchanged between the two).
    Separate,
    /// j receives nothing: an own-support sum (a Shepard or summation density, the
    /// continuity equation's `Σ_{j∈H_i}`, a gradient or a correction matrix).
    OneSided,
}

/// A term's handle on one accumulator of its own column (not the force or a scalar register,
/// which [`crate::pair::Out`] has by place): its owner channels start at `i`,
/// its neighbour channels (only with [`Reaction::Separate`]) at `j`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Acc {
    pub(crate) i: u16,
    pub(crate) j: u16,
    pub(crate) at: u16,
}

/// Sets a particle's column from its finished sum: `(column, Σ, m_i)`.
pub trait Finish<C>: Fn(&mut C, &[Real], Real) + Copy + Send + Sync + 'static {}

impl<C, F: Fn(&mut C, &[Real], Real) + Copy + Send + Sync + 'static> Finish<C> for F {}

/// Writes the finished sums of one accumulator into its column (sums, stride, first
/// channel); false when the particles lack the column.
type Writer = std::sync::Arc<dyn Fn(&mut World, &[Real], usize, usize) -> bool + Send + Sync>;

/// How many scalar registers a sweep has ([`Standard::Scalar`]).
pub const SCALAR_REGISTERS: usize = 2;

/// The sums a sweep keeps in registers, by place in [`crate::pair::Out`]: the force and
/// [`SCALAR_REGISTERS`] scalars. The first declarations of a sweep take them — whatever
/// column each goes into ([`Binder::force`], [`Binder::scalar_register`]) — and the row loop
/// is compiled for them, so a term that writes a column of its own through a register runs
/// at the same cost as one that writes a built-in column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    /// The force (a vector whose reaction is opposite), into the acceleration.
    Force,
    /// Scalar register `k` (`k < SCALAR_REGISTERS`).
    Scalar(usize),
}

/// One accumulator of a sweep.
#[derive(Clone)]
pub struct AccumulatorSlot {
    /// The column's short type name.
    pub name: String,
    type_id: TypeId,
    /// Reals per particle.
    pub width: usize,
    /// How pairs reach the neighbour.
    pub reaction: Reaction,
    write: Writer,
    /// Its place in each particle's sums.
    pub i: usize,
    /// One of the standard sums, or `None` for a column's own channels.
    pub standard: Option<Standard>,
    /// Its first owner channel in [`crate::pair::Out`] (not standard).
    pub chan: usize,
    /// Its first neighbour channel (not standard, [`Reaction::Separate`]).
    pub j: Option<usize>,
    /// Skipped when the particles lack the column.
    optional: bool,
}

impl std::fmt::Debug for AccumulatorSlot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}[{}; {:?}] at {}",
            self.name, self.width, self.reaction, self.i
        )
    }
}

/// The sums of one sweep: the accumulators in declaration order, `owner` reals of sums per
/// particle, and the owner and neighbour channels of the non-standard ones.
#[derive(Clone, Debug, Default)]
pub struct Layout {
    /// The accumulators.
    pub slots: Vec<AccumulatorSlot>,
    /// Reals per particle of the sums.
    pub owner: usize,
    /// Owner channels of the non-standard accumulators.
    pub extra_owner: usize,
    /// Neighbour channels of the non-standard accumulators.
    pub extra_neighbour: usize,
}

/// Where one reaction channel of a support slot comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Component `c` of the force, negated.
    Force(usize),
    /// Scalar register `k` to j.
    Scalar(usize),
    /// A non-standard owner channel, negated ([`Reaction::Opposite`]).
    Owner(usize),
    /// A non-standard neighbour channel ([`Reaction::Separate`]).
    Neighbour(usize),
}

/// One reaction channel of a support slot: where it comes from and where it lands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReactionChannel {
    /// The pair's value it carries.
    pub source: Source,
    /// The place in j's sums it adds to.
    pub target: usize,
}

impl Layout {
    /// The reaction channels stored per support slot: the standard ones first (the force's
    /// components, then the scalar registers), then the others in layout order — so that
    /// a sweep of standard sums has its channels at fixed places (see
    /// [`crate::block::row::RowPlan`]).
    pub fn reactions<V: Vector>(&self) -> Vec<ReactionChannel> {
        let mut out = self.reactions_in_slot_order::<V>();
        let rank = |r: &ReactionChannel| match r.source {
            Source::Force(c) => c,
            Source::Scalar(k) => 3 + k,
            Source::Owner(_) | Source::Neighbour(_) => 3 + SCALAR_REGISTERS,
        };
        // stable: the others keep their order
        out.sort_by_key(rank);
        out
    }

    fn reactions_in_slot_order<V: Vector>(&self) -> Vec<ReactionChannel> {
        let mut out = Vec::new();
        for s in &self.slots {
            for c in 0..s.width {
                let source = match (s.standard, s.reaction) {
                    (_, Reaction::OneSided) => continue,
                    (Some(Standard::Force), _) => Source::Force(c),
                    (Some(Standard::Scalar(k)), _) => Source::Scalar(k),
                    (None, Reaction::Opposite) => Source::Owner(s.chan + c),
                    (None, Reaction::Separate) => match s.j {
                        Some(j) => Source::Neighbour(j + c),
                        None => continue,
                    },
                };
                out.push(ReactionChannel {
                    source,
                    target: s.i + c,
                });
            }
        }
        debug_assert!(
            out.iter()
                .all(|r| !matches!(r.source, Source::Force(c) if c >= V::DIM))
        );
        out
    }

    /// True when some accumulator writes column `C`.
    pub fn writes<C: 'static>(&self) -> bool {
        self.slots.iter().any(|s| s.type_id == TypeId::of::<C>())
    }

    /// The slot of column `C`.
    pub fn slot<C: 'static>(&self) -> Option<&AccumulatorSlot> {
        self.slots.iter().find(|s| s.type_id == TypeId::of::<C>())
    }

    /// The place in each particle's sums of the standard sum `k`.
    pub fn standard(&self, k: Standard) -> Option<&AccumulatorSlot> {
        self.slots.iter().find(|s| s.standard == Some(k))
    }

    /// Writes every accumulator's finished sums (`sums`: one row of `self.owner` reals per
    /// particle, row order) into its column.
    pub fn write(&self, world: &mut World, sums: &[Real]) {
        for s in &self.slots {
            let written = (s.write)(world, sums, self.owner, s.i);
            debug_assert!(written || s.optional, "{} was bound but is missing", s.name);
        }
    }

    fn declare<C: Component<Mutability = Mutable>>(
        &mut self,
        (reaction, width, standard): (Reaction, usize, Option<Standard>),
        finish: impl Finish<C>,
        optional: bool,
    ) -> Result<Acc, String> {
        let name = dualsph_core::sim::short_type_name(std::any::type_name::<C>()).to_string();
        if !(1..=9).contains(&width) {
            return Err(format!(
                "{name}: a sum has 1 to 9 reals per particle, not {width}"
            ));
        }
        let extra = if standard.is_some() { 0 } else { width };
        let to_j = if reaction == Reaction::Separate {
            extra
        } else {
            0
        };
        if self.extra_owner + extra > MAX_OWNER_CHANNELS
            || self.extra_neighbour + to_j > MAX_NEIGHBOUR_CHANNELS
        {
            return Err(format!(
                "{name}: a sweep carries at most {MAX_OWNER_CHANNELS} reals of its own columns \
                 per pair and {MAX_NEIGHBOUR_CHANNELS} to neighbours; put this term in a sweep of \
                 its own"
            ));
        }
        if let Some(taken) = standard.and_then(|k| self.standard(k))
            && taken.type_id != TypeId::of::<C>()
        {
            return Err(format!(
                "{name}: its register ({:?}) already holds {}; put this term in a sweep of its \
                 own or use another register",
                standard.expect("a register"),
                taken.name
            ));
        }
        if let Some(k) = self
            .slots
            .iter()
            .position(|s| s.type_id == TypeId::of::<C>())
        {
            let s = &self.slots[k];
            let merged = match (s.reaction, reaction) {
                (a, b) if a == b => a,
                (Reaction::OneSided, Reaction::Separate)
                | (Reaction::Separate, Reaction::OneSided) => Reaction::Separate,
                (a, b) => {
                    return Err(format!(
                        "{name} is summed with {a:?} by one term and {b:?} by another: a force-like \
                         sum (Opposite) cannot share its column with another kind"
                    ));
                }
            };
            if merged == Reaction::Separate && s.j.is_none() && s.standard.is_none() {
                self.slots[k].j = Some(self.extra_neighbour);
                self.extra_neighbour += width;
            }
            self.slots[k].reaction = merged;
            let s = &self.slots[k];
            return Ok(handle(s));
        }
        let j = (reaction == Reaction::Separate && standard.is_none()).then(|| {
            self.extra_neighbour += width;
            self.extra_neighbour - width
        });
        self.slots.push(AccumulatorSlot {
            name,
            type_id: TypeId::of::<C>(),
            width,
            reaction,
            write: std::sync::Arc::new(move |world, sums, stride, at| {
                write_column(world, sums, (stride, at, width), finish)
            }),
            i: self.owner,
            standard,
            chan: self.extra_owner,
            j,
            optional,
        });
        self.owner += width;
        self.extra_owner += extra;
        Ok(handle(self.slots.last().expect("just pushed")))
    }
}

fn handle(s: &AccumulatorSlot) -> Acc {
    Acc {
        at: s.i as u16,
        i: s.chan as u16,
        j: s.j.map_or(u16::MAX, |j| j as u16),
    }
}

/// Sets every particle's `C` with `finish(C, Σ, m)`; false when the particles lack `C`.
fn write_column<C: Component<Mutability = Mutable>>(
    world: &mut World,
    sums: &[Real],
    (stride, at, width): (usize, usize, usize),
    finish: impl Finish<C>,
) -> bool {
    let Some(mut q) = world.try_query::<(&Mass, &mut C)>() else {
        return false;
    };
    let Ok(tables) = q.contiguous_iter_mut(world) else {
        return false;
    };
    let Some((mass, mut cols)) = single_table(tables) else {
        return true;
    };
    // pieces of MIN_LEN particles, each a plain loop (rayon's per-item calls cost more than
    // the finish itself)
    let piece = dualsph_core::chunks::MIN_LEN;
    let (lo, hi) = (at, at + width);
    // checked once here, so that the loop cuts each particle's sums with no test
    assert!(
        lo <= hi && hi <= stride,
        "a sum lies inside its particle's row"
    );
    cols.bypass_change_detection()
        .par_chunks_mut(piece)
        .zip(sums.par_chunks(stride * piece))
        .zip(mass.par_chunks(piece))
        .for_each(|((cols, sums), mass)| {
            for ((c, s), m) in cols.iter_mut().zip(sums.chunks_exact(stride)).zip(mass) {
                finish(c, &s[lo..hi], m.0);
            }
        });
    true
}

/// What a term sees when it is bound for a sweep: the particles' columns to read, and the
/// sweep's accumulators to declare the sums it writes.
pub struct Binder<'l, 'w, V: Vector> {
    data: ParticleData<'w, V>,
    kernel: &'w Kernel,
    layout: &'l mut Layout,
    term: String,
}

impl<'l, 'w, V: Vector> Binder<'l, 'w, V> {
    /// A binder for `term` over `data` with `kernel`, declaring into `layout`.
    pub fn new(
        data: ParticleData<'w, V>,
        kernel: &'w Kernel,
        layout: &'l mut Layout,
        term: &str,
    ) -> Self {
        Binder {
            data,
            kernel,
            layout,
            term: term.to_string(),
        }
    }

    /// The particles' core columns.
    pub fn data(&self) -> ParticleData<'w, V> {
        self.data
    }

    /// The scene's kernel.
    pub fn kernel(&self) -> &'w Kernel {
        self.kernel
    }

    /// The column of `C`, or `None` when the particles do not have it.
    pub fn column<C: Component>(&self) -> Option<&'w [C]> {
        self.data.column()
    }

    /// The column of `C`; the error names the term and says that no plugin added it.
    pub fn require<C: Component>(&self) -> Result<&'w [C], String> {
        self.data.require(&self.term)
    }

    /// Declares a sum into column `C`, `width` reals per particle, with `reaction`; after the
    /// sweep `finish(C, Σ, m_i)` sets each particle's column. The error names the term when
    /// the particles lack `C` or another term sums `C` with an incompatible reaction.
    pub fn accumulate<C: Component<Mutability = Mutable>>(
        &mut self,
        reaction: Reaction,
        width: usize,
        finish: impl Finish<C>,
    ) -> Result<Acc, String> {
        self.require::<C>()?;
        self.layout
            .declare::<C>((reaction, width, None), finish, false)
            .map_err(|e| format!("{}: {e}", self.term))
    }

    /// Declares a sum into a registered column `C` (scalar, vector or matrix), set to the sum
    /// as it is.
    pub fn accumulate_column<C: ColumnValue<V>>(
        &mut self,
        reaction: Reaction,
    ) -> Result<Acc, String> {
        if C::SHAPE == Shape::Record {
            return Err(format!(
                "{}: {} is a record column; declare its sum with accumulate",
                self.term,
                dualsph_core::sim::short_type_name(std::any::type_name::<C>())
            ));
        }
        self.accumulate::<C>(reaction, C::width(), |c: &mut C, s: &[Real], _| c.take(s))
    }

    /// Declares that the term adds to the force on each particle (`m_i a_i`,
    /// [`Reaction::Opposite`], with [`crate::pair::Out::add_force`]), which goes into its
    /// [`Acceleration`] (divided by `m_i`).
    pub fn force(&mut self) -> Result<(), String> {
        self.require::<Acceleration<V>>()?;
        let finish = |a: &mut Acceleration<V>, s: &[Real], m: Real| a.0 = take_vector::<V>(s) / m;
        self.layout
            .declare(
                (Reaction::Opposite, V::DIM, Some(Standard::Force)),
                finish,
                false,
            )
            .map(drop)
            .map_err(|e| format!("{}: {e}", self.term))
    }

    /// Declares that the term adds to scalar register `K` (`K <` [`SCALAR_REGISTERS`]) with
    /// `reaction` ([`crate::pair::Out::add_scalar`] and, with [`Reaction::Separate`],
    /// [`crate::pair::Out::react_scalar`]); after the sweep `finish(C, Σ, m_i)` sets each
    /// particle's `C`, and nothing when the particles lack `C` (a sum the scene does not
    /// keep). The error names the term when another term of the sweep holds the register for
    /// another column, or sums `C` with a force-like reaction.
    pub fn scalar_register<C: Component<Mutability = Mutable>, const K: usize>(
        &mut self,
        reaction: Reaction,
        finish: impl Finish<C>,
    ) -> Result<(), String> {
        const {
            assert!(
                K < SCALAR_REGISTERS,
                "a sweep has SCALAR_REGISTERS scalar registers"
            )
        };
        if reaction == Reaction::Opposite {
            return Err(format!(
                "{}: a scalar register carries an own-support or a separate reaction, not an \
                 opposite one; declare a force-like scalar with accumulate",
                self.term
            ));
        }
        let optional = self.column::<C>().is_none();
        self.layout
            .declare((reaction, 1, Some(Standard::Scalar(K))), finish, optional)
            .map(drop)
            .map_err(|e| format!("{}: {e}", self.term))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::math::Vector;
    use glam::DVec2;

    /// A matrix column (a velocity gradient, say).
    #[derive(Component)]
    struct VelocityGradient<V: Vector>(#[allow(dead_code)] V::Mat);

    /// Another matrix column (a correction, say).
    #[derive(Component)]
    struct GradientCorrection<V: Vector>(#[allow(dead_code)] V::Mat);

    /// Two columns that both ask for scalar register 0.
    #[derive(Component)]
    struct First(#[allow(dead_code)] Real);
    #[derive(Component)]
    struct Second(#[allow(dead_code)] Real);

    #[test]
    fn a_register_holds_one_column() {
        let mut l = Layout::default();
        let none = |_: &mut First, _: &[Real], _: Real| {};
        let a = l.declare::<First>(
            (Reaction::Separate, 1, Some(Standard::Scalar(0))),
            none,
            true,
        );
        assert!(a.is_ok());
        let again = l.declare::<First>(
            (Reaction::Separate, 1, Some(Standard::Scalar(0))),
            none,
            true,
        );
        assert!(again.is_ok(), "the same column shares its register");
        let none = |_: &mut Second, _: &[Real], _: Real| {};
        let clash = l.declare::<Second>(
            (Reaction::Separate, 1, Some(Standard::Scalar(0))),
            none,
            true,
        );
        let e = clash.unwrap_err();
        assert!(
            e.contains("Second") && e.contains("already holds First"),
            "{e}"
        );
        let other = l.declare::<Second>(
            (Reaction::OneSided, 1, Some(Standard::Scalar(1))),
            none,
            true,
        );
        assert!(other.is_ok());
        assert_eq!(l.owner, 2);
    }

    #[test]
    fn declarations_share_a_column_and_upgrade_one_sided_to_separate() {
        let mut l = Layout::default();
        let none = |_: &mut Acceleration<DVec2>, _: &[Real], _: Real| {};
        let f = l.declare::<Acceleration<DVec2>>(
            (Reaction::Opposite, 2, Some(Standard::Force)),
            none,
            false,
        );
        let d = l.declare::<VelocityGradient<DVec2>>(
            (Reaction::OneSided, 4, None),
            |_: &mut _, _: &[Real], _: Real| {},
            false,
        );
        assert_eq!(f.map(|a| a.i), Ok(0));
        assert_eq!(
            d,
            Ok(Acc {
                i: 0,
                j: u16::MAX,
                at: 2
            })
        );
        let d2 = l.declare::<VelocityGradient<DVec2>>(
            (Reaction::Separate, 4, None),
            |_: &mut _, _: &[Real], _: Real| {},
            false,
        );
        assert_eq!(d2, Ok(Acc { i: 0, j: 0, at: 2 }));
        let m = l.declare::<GradientCorrection<DVec2>>(
            (Reaction::OneSided, 4, None),
            |_: &mut _, _: &[Real], _: Real| {},
            false,
        );
        assert_eq!(
            m,
            Ok(Acc {
                i: 4,
                j: u16::MAX,
                at: 6
            })
        );
        assert_eq!((l.owner, l.extra_owner, l.extra_neighbour), (10, 8, 4));
        let r = l.reactions::<DVec2>();
        assert_eq!(r.len(), 6);
        assert_eq!(
            r[0],
            ReactionChannel {
                source: Source::Force(0),
                target: 0
            }
        );
        assert_eq!(
            r[2],
            ReactionChannel {
                source: Source::Neighbour(0),
                target: 2
            }
        );
        let clash = l.declare::<VelocityGradient<DVec2>>(
            (Reaction::Opposite, 4, None),
            |_: &mut _, _: &[Real], _: Real| {},
            false,
        );
        assert!(clash.unwrap_err().contains("VelocityGradient"));
    }
}

//! What a build is given and how it fails: `PlannerOptions` (stage observer, solve method,
//! multigrid, cancellation, conductivity, threads), the stages, `CarParams`.

use super::*;

/// A stage of [`Planner::with_options`], reported to [`PlannerOptions::on_stage`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Validating the scene and meshing its free space.
    Meshing,
    /// Assembling the finite element system.
    Assembling,
    /// Factoring and solving for the potential.
    Solving,
    /// The planner is built.
    Done,
}

/// Something told of each [`Stage`] as it starts (the command line draws a spinner with it).
pub type StageObserver = Arc<dyn Fn(Stage) + Send + Sync>;

/// Asked at the start of each [`Stage`] whether to stop building (true: stop).
pub type CancelCheck = Arc<dyn Fn() -> bool + Send + Sync>;

/// The conductivity k(x) > 0 of ∇·(k∇φ) = 0 at a point (taken at each triangle's centroid).
pub type Conductivity = Arc<dyn Fn(Point) -> f64 + Send + Sync>;

/// The absorption σ(x) ≥ 0 of −∇·(k∇φ) + σ(φ − c) = 0 at a point, in 1/m² (taken at each
/// triangle's centroid; c is the walls' level).
pub type Absorption = Arc<dyn Fn(Point) -> f64 + Send + Sync>;

/// How to build a planner.
#[derive(Clone, Default)]
pub struct PlannerOptions {
    /// Called as each stage starts, and with [`Stage::Done`] at the end.
    pub on_stage: Option<StageObserver>,
    /// Threads for the Cholesky solve of the potential (by default rayon's pool from
    /// [`harmonic_solver::PARALLEL_MIN_UNKNOWNS`] unknowns). The same paths to rounding either
    /// way. The mesher's two halves (large meshes) run on two threads of rayon's pool where it
    /// has two.
    pub parallelism: Parallelism,
    /// How the potential's system is factored ([`SolveMethod::Auto`] by default: the
    /// accurate LDLᵀ up to [`harmonic_fem::AUTO_ACCURATE_MAX_UNKNOWNS`] unknowns, Cholesky
    /// above, redone accurately when ψ spans too many orders of magnitude).
    pub solve: SolveMethod,
    /// `Some(k)`: mesh at `4^k` times the scene's largest triangle area (its default when
    /// it sets none), refine that mesh uniformly `k` times ([`MeshHierarchy`]: the same
    /// smallest angle, triangles of at most the area asked) and solve by conjugate gradients
    /// with a multigrid V-cycle over those levels ([`MultilevelSystem`]) instead of a
    /// factorisation. Its work grows linearly with the mesh (the 1 M-triangle reference
    /// scene plans in under half the direct route's time), but ψ is right only to about
    /// 1e-10 of its largest value, so it is checked
    /// ([`MultilevelSystem::checked_potential`]: no negative ψ, no zero beside a positive
    /// one, no interior extremum) and, where it fails (a maze or corridor whose ψ falls far
    /// below that), the finest level is factored directly on the same mesh. Scene planners
    /// only ([`Planner::with_options`], [`Planner::with_constraints`]); others refuse
    /// `k ≥ 1` with [`PlanError::MultigridUnsupported`]. `Some(0)`: the direct solve on the
    /// scene's own mesh. `None` (the default): [`crate::AUTO_MULTIGRID_REFINEMENTS`] for a
    /// scene whose mesh is estimated at [`crate::AUTO_MULTIGRID_FROM`] triangles or more
    /// (with [`SolveMethod::Auto`], no conductivity and no blend), else 0.
    pub multigrid: Option<usize>,
    /// Asked at the start of every stage (meshing, assembling, solving); when it returns
    /// true the build stops there with [`PlanError::Cancelled`]. A stage already running
    /// finishes first.
    pub cancel: Option<CancelCheck>,
    /// `Some(k)`: the potential solves ∇·(k∇φ) = 0, k taken at each triangle's centroid
    /// ([`harmonic_fem::Assembler::with_conductivity`]): where k is small the flow, and the
    /// paths, go around (a map's graded costs, [`crate::map::MapOptions::cost_weight`]).
    /// Direct solves only: the multigrid route and the blend refuse it.
    pub conductivity: Option<Conductivity>,
    /// `Some(σ)`: the potential solves −∇·(k∇φ) + σ(φ − c) = 0, σ taken at each triangle's
    /// centroid ([`harmonic_fem::Assembler::with_absorption`]): where σ > 0 the potential is
    /// drawn toward the walls' level, so paths keep away from there as from walls (a map's
    /// graded costs, [`crate::map::MapOptions::cost_weight`]). Direct solves only, as
    /// [`PlannerOptions::conductivity`].
    pub absorption: Option<Absorption>,
    /// Threads for the whole build (meshing, assembly, the solve) and for tracing many
    /// starts ([`Planner::plan_many`], [`Planner::plan_report`]): `None` (the default) uses
    /// rayon's global pool, every core or `RAYON_NUM_THREADS`; `Some(n)` a pool of `n`
    /// threads the planner keeps. Paths are the same at any count.
    pub threads: Option<usize>,
}

impl PlannerOptions {
    /// Tells the observer, if any, that `stage` starts, after asking [`PlannerOptions::cancel`]
    /// whether to stop.
    pub(crate) fn stage(&self, stage: Stage) -> Result<(), PlanError> {
        if stage != Stage::Done && self.cancel.as_ref().is_some_and(|c| c()) {
            return Err(PlanError::Cancelled { stage });
        }
        if let Some(observe) = &self.on_stage {
            observe(stage);
        }
        Ok(())
    }
}

impl std::fmt::Debug for PlannerOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PlannerOptions")
            .field("on_stage", &self.on_stage.as_ref().map(|_| "observer"))
            .field("parallelism", &self.parallelism)
            .field("solve", &self.solve)
            .field("multigrid", &self.multigrid)
            .field("cancel", &self.cancel.as_ref().map(|_| "check"))
            .field("conductivity", &self.conductivity.as_ref().map(|_| "k(x)"))
            .field("absorption", &self.absorption.as_ref().map(|_| "σ(x)"))
            .field("threads", &self.threads)
            .finish()
    }
}

/// A car-like robot: rear-wheel drive, front-wheel steering.
#[derive(Clone, Copy, Debug)]
pub struct CarParams {
    /// Distance between the axles.
    pub wheelbase: f64,
    /// Steering limit of the front wheels, radians.
    pub max_steer: f64,
    /// Arc length per step.
    pub step: f64,
    /// Check a rectangular footprint (1.25 L × 0.6 L) against the obstacles every step.
    pub check_footprint: bool,
}

impl CarParams {
    /// Defaults sized from the scene: a wheelbase of 2 % of the scene's size, 35° steering,
    /// steps of a tenth of the wheelbase.
    pub fn for_scene(planner: &Planner) -> CarParams {
        let wheelbase = 0.02 * planner.scale;
        CarParams {
            wheelbase,
            max_steer: 35f64.to_radians(),
            step: 0.1 * wheelbase,
            check_footprint: false,
        }
    }

    pub(crate) fn options(&self) -> CarOptions {
        CarOptions::new(self.wheelbase, self.max_steer, self.step)
    }

    /// Checks the ranges of the parameters.
    pub fn validate(&self) -> Result<(), PlanError> {
        self.options().validate()?;
        Ok(())
    }
}

//! One vocabulary for the three planners: [`PlannerApi`] (plan, plan_many, report, svg,
//! vtu, export), which the plane's [`Planner`], [`VolumePlanner`] and [`ConfigPlanner`] implement, a
//! report that says itself in words ([`Summary`]), and [`AnyPlanner`], the planner of any scene file
//! ([`AnyScene`]) with one output path.
//!
//! ```
//! use harmonic_planner::{AnyPlanner, AnyScene, PlannerOptions, Summary};
//! let scene = AnyScene::from_json(r#"{
//!     "workspace": [[0, 0], [4, 0], [4, 4], [0, 4]],
//!     "obstacles": [{"circle": {"center": [2, 2], "radius": 0.5}}],
//!     "goal": {"point": [3.5, 3.5]},
//!     "starts": [[0.5, 0.5]]
//! }"#)?;
//! let planner = AnyPlanner::new(&scene, &PlannerOptions::default())?;
//! let report = planner.report(&scene.starts())?;
//! assert!(report.summary().contains("reached_goal"));
//! assert!(planner.vtu()?.starts_with("<?xml"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use harmonic_types::Point3;
use serde::Serialize;

use crate::PlanError;
use crate::cspace::{ConfigPlanReport, ConfigPlannedPath, ConfigPlanner};
use crate::planner::{
    Export, PathSummary, PlanReport, PlannedPath, Planner, PlannerOptions, Report, SvgOptions,
};
use crate::scene::AnyScene;
use crate::volume::{VolumeError, VolumeExport, VolumePlanReport, VolumePlanner};

/// A report of several starts, as `hplan plan --json` prints it, that can also say itself as
/// text (`hplan plan` without `--json`).
pub trait Summary: Serialize {
    /// A human-readable summary: mesh, timings, potential, one line per path.
    fn summary(&self) -> String;
}

impl<P, M> Summary for Report<P, M>
where
    P: PathSummary + Serialize,
    M: std::fmt::Display + Serialize,
{
    fn summary(&self) -> String {
        Report::summary(self)
    }
}

/// Why a planner's mesh and potential could not be written as VTK.
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct VtuError(#[from] VolumeError);

/// What every planner answers, whatever its space: the plane, a volume, a configuration
/// space. Built once from its scene, queried many times.
pub trait PlannerApi {
    /// A start: a point of the plane, a point in space, or a configuration.
    type Start: Sync;
    /// One planned path.
    type Path: Serialize;
    /// The report of several starts.
    type Report: Summary;
    /// Plans from `start`.
    fn plan(&self, start: &Self::Start) -> Self::Path;
    /// Plans from every start, in parallel.
    fn plan_many(&self, starts: &[Self::Start]) -> Vec<Self::Path>;
    /// Plans from every start and reports mesh, timings, potential and paths.
    fn report(&self, starts: &[Self::Start]) -> Self::Report;
    /// The space, the potential where it can be drawn and the report's paths, as SVG.
    fn svg(&self, report: &Self::Report, options: &SvgOptions) -> String;
    /// The mesh with φ, ψ and ∇φ as a VTK unstructured grid, for ParaView.
    fn vtu(&self) -> Result<String, VtuError>;
    /// The mesh and the potential for outside tools (`hplan export --potential`).
    type Export: Serialize;
    /// The mesh and the potential, as [`PlannerApi::Export`].
    fn export(&self) -> Self::Export;
}

impl PlannerApi for Planner {
    type Start = [f64; 2];
    type Path = PlannedPath;
    type Report = PlanReport;
    fn plan(&self, start: &[f64; 2]) -> PlannedPath {
        Planner::plan(self, *start)
    }
    fn plan_many(&self, starts: &[[f64; 2]]) -> Vec<PlannedPath> {
        Planner::plan_many(self, starts)
    }
    fn report(&self, starts: &[[f64; 2]]) -> PlanReport {
        self.plan_report(starts)
    }
    fn svg(&self, report: &PlanReport, options: &SvgOptions) -> String {
        let paths: Vec<_> = report.paths.iter().map(|p| p.points.clone()).collect();
        Planner::svg(self, &paths, &[], options)
    }
    fn vtu(&self) -> Result<String, VtuError> {
        Ok(Planner::vtu(self))
    }
    type Export = Export;
    fn export(&self) -> Export {
        Planner::export(self)
    }
}

impl PlannerApi for VolumePlanner {
    type Start = [f64; 3];
    type Path = PlannedPath<Point3>;
    type Report = VolumePlanReport;
    fn plan(&self, start: &[f64; 3]) -> PlannedPath<Point3> {
        VolumePlanner::plan(self, *start)
    }
    fn plan_many(&self, starts: &[[f64; 3]]) -> Vec<PlannedPath<Point3>> {
        VolumePlanner::plan_many(self, starts)
    }
    fn report(&self, starts: &[[f64; 3]]) -> VolumePlanReport {
        self.plan_report(starts)
    }
    /// The three orthographic projections; `options` are the plane's and are not used.
    fn svg(&self, report: &VolumePlanReport, _options: &SvgOptions) -> String {
        let paths: Vec<_> = report.paths.iter().map(|p| p.points.clone()).collect();
        VolumePlanner::svg(self, &paths)
    }
    fn vtu(&self) -> Result<String, VtuError> {
        Ok(VolumePlanner::vtu(self)?)
    }
    type Export = VolumeExport;
    fn export(&self) -> VolumeExport {
        VolumePlanner::export(self)
    }
}

impl PlannerApi for ConfigPlanner {
    type Start = Vec<f64>;
    type Path = ConfigPlannedPath;
    type Report = ConfigPlanReport;
    fn plan(&self, start: &Vec<f64>) -> ConfigPlannedPath {
        ConfigPlanner::plan(self, start)
    }
    fn plan_many(&self, starts: &[Vec<f64>]) -> Vec<ConfigPlannedPath> {
        ConfigPlanner::plan_many(self, starts)
    }
    fn report(&self, starts: &[Vec<f64>]) -> ConfigPlanReport {
        self.plan_report(starts)
    }
    /// The robot along each path; of `options` only the title is used.
    fn svg(&self, report: &ConfigPlanReport, options: &SvgOptions) -> String {
        let paths: Vec<_> = report.paths.iter().map(|p| p.configurations()).collect();
        ConfigPlanner::svg(self, &paths, options.title.clone())
    }
    fn vtu(&self) -> Result<String, VtuError> {
        Ok(ConfigPlanner::vtu(self)?)
    }
    /// The slab of one period, in the space's scaled coordinates.
    type Export = VolumeExport;
    fn export(&self) -> VolumeExport {
        ConfigPlanner::export(self)
    }
}

/// A start whose number of coordinates does not fit the scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("start {}: expected {expected}", start.iter().map(f64::to_string).collect::<Vec<_>>().join(","))]
pub struct StartError {
    /// The start as given.
    pub start: Vec<f64>,
    /// What the scene takes (`X,Y,Z on a volume scene`, `3 numbers (X,Y,THETA)`).
    pub expected: String,
}

/// The planner of any scene file: a plane, a volume, or a polygon or arm robot.
pub enum AnyPlanner {
    /// A plane scene's.
    Plane(Box<Planner>),
    /// A volume scene's.
    Volume(Box<VolumePlanner>),
    /// A configuration-space scene's.
    Config(Box<ConfigPlanner>),
}

impl std::fmt::Debug for AnyPlanner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self {
            AnyPlanner::Plane(_) => "plane",
            AnyPlanner::Volume(_) => "volume",
            AnyPlanner::Config(_) => "configuration space",
        };
        f.debug_struct("AnyPlanner")
            .field("kind", &kind)
            .finish_non_exhaustive()
    }
}

/// The report of any planner; serialised as that planner's report.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum AnyReport {
    /// A plane scene's.
    Plane(PlanReport),
    /// A volume scene's.
    Volume(VolumePlanReport),
    /// A configuration-space scene's.
    Config(ConfigPlanReport),
}

/// The mesh and potential of any planner, serialised as that planner's export.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum AnyExport {
    /// A plane scene's.
    Plane(Export),
    /// A volume's or a configuration space's slab.
    Tetrahedra(VolumeExport),
}

impl Summary for AnyReport {
    fn summary(&self) -> String {
        match self {
            AnyReport::Plane(r) => r.summary(),
            AnyReport::Volume(r) => r.summary(),
            AnyReport::Config(r) => r.summary(),
        }
    }
}

impl AnyPlanner {
    /// Builds the planner of `scene`. `options` shape a plane scene's build (stages, solve
    /// method, multigrid, threads); a volume or a configuration space is built as its scene
    /// says.
    pub fn new(scene: &AnyScene, options: &PlannerOptions) -> Result<AnyPlanner, PlanError> {
        Ok(match scene {
            AnyScene::Plane(s) => AnyPlanner::Plane(Box::new(Planner::with_options(s, options)?)),
            AnyScene::Volume(s) => AnyPlanner::Volume(Box::new(VolumePlanner::new(s)?)),
            AnyScene::Config(s) => AnyPlanner::Config(Box::new(ConfigPlanner::new(s)?)),
        })
    }

    /// Plans from every start (each as many numbers as the scene's space has dimensions)
    /// and reports; an error names the first start of the wrong size.
    pub fn report(&self, starts: &[Vec<f64>]) -> Result<AnyReport, StartError> {
        fn fixed<const N: usize>(
            starts: &[Vec<f64>],
            what: &str,
        ) -> Result<Vec<[f64; N]>, StartError> {
            starts
                .iter()
                .map(|s| {
                    <[f64; N]>::try_from(s.as_slice()).map_err(|_| StartError {
                        start: s.clone(),
                        expected: what.to_string(),
                    })
                })
                .collect()
        }
        Ok(match self {
            AnyPlanner::Plane(p) => AnyReport::Plane(PlannerApi::report(
                &**p,
                &fixed(starts, "X,Y on a plane scene")?,
            )),
            AnyPlanner::Volume(p) => AnyReport::Volume(PlannerApi::report(
                &**p,
                &fixed(starts, "X,Y,Z on a volume scene")?,
            )),
            AnyPlanner::Config(p) => {
                let dof = p.space().dof();
                if let Some(bad) = starts.iter().find(|s| s.len() != dof) {
                    let names = match p.space().robot() {
                        harmonic_cspace::Robot::Rigid(_) => "X,Y,THETA",
                        harmonic_cspace::Robot::Arm(_) => "the joint angles",
                    };
                    return Err(StartError {
                        start: bad.clone(),
                        expected: format!("{dof} numbers ({names})"),
                    });
                }
                AnyReport::Config(PlannerApi::report(&**p, starts))
            }
        })
    }

    /// The report's paths drawn (see [`PlannerApi::svg`]); a report of another planner's
    /// kind draws none of its paths.
    pub fn svg(&self, report: &AnyReport, options: &SvgOptions) -> String {
        match (self, report) {
            (AnyPlanner::Plane(p), AnyReport::Plane(r)) => PlannerApi::svg(&**p, r, options),
            (AnyPlanner::Volume(p), AnyReport::Volume(r)) => PlannerApi::svg(&**p, r, options),
            (AnyPlanner::Config(p), AnyReport::Config(r)) => PlannerApi::svg(&**p, r, options),
            (AnyPlanner::Plane(p), _) => {
                PlannerApi::svg(&**p, &p.plan_report::<[f64; 2]>(&[]), options)
            }
            (AnyPlanner::Volume(p), _) => PlannerApi::svg(&**p, &p.plan_report(&[]), options),
            (AnyPlanner::Config(p), _) => PlannerApi::svg(&**p, &p.plan_report(&[]), options),
        }
    }

    /// The mesh and the potential for outside tools (see [`PlannerApi::export`]).
    pub fn export(&self) -> AnyExport {
        match self {
            AnyPlanner::Plane(p) => AnyExport::Plane(PlannerApi::export(&**p)),
            AnyPlanner::Volume(p) => AnyExport::Tetrahedra(PlannerApi::export(&**p)),
            AnyPlanner::Config(p) => AnyExport::Tetrahedra(PlannerApi::export(&**p)),
        }
    }

    /// The mesh and potential as VTK (see [`PlannerApi::vtu`]).
    pub fn vtu(&self) -> Result<String, VtuError> {
        match self {
            AnyPlanner::Plane(p) => PlannerApi::vtu(&**p),
            AnyPlanner::Volume(p) => PlannerApi::vtu(&**p),
            AnyPlanner::Config(p) => PlannerApi::vtu(&**p),
        }
    }
}

impl AnyScene {
    /// Checks that every start has as many numbers as the scene's space has dimensions
    /// (before anything is built).
    pub fn check_starts(&self, starts: &[Vec<f64>]) -> Result<(), StartError> {
        let (dof, expected) = match self {
            AnyScene::Plane(_) => (2, "X,Y on a plane scene".to_string()),
            AnyScene::Volume(_) => (3, "X,Y,Z on a volume scene".to_string()),
            AnyScene::Config(s) => match &s.robot.arm {
                Some(arm) => (
                    arm.links.len(),
                    format!("{} numbers (the joint angles)", arm.links.len()),
                ),
                None => (3, "3 numbers (X,Y,THETA)".to_string()),
            },
        };
        match starts.iter().find(|s| s.len() != dof) {
            Some(bad) => Err(StartError {
                start: bad.clone(),
                expected,
            }),
            None => Ok(()),
        }
    }

    /// The scene's own starts, as coordinate lists (`"starts"`).
    pub fn starts(&self) -> Vec<Vec<f64>> {
        match self {
            AnyScene::Plane(s) => s.starts.iter().map(|p| p.to_vec()).collect(),
            AnyScene::Volume(s) => s.starts.iter().map(|p| p.to_vec()).collect(),
            AnyScene::Config(s) => s.starts.clone(),
        }
    }
}

//! What can go wrong in a command, typed: the argument at fault, the file it concerns, or the
//! library's own error (which names the part of the scene or map).

use std::path::PathBuf;

use harmonic_planner::map::MapError;
use harmonic_planner::map::movingai::MovingAiError;
use harmonic_planner::{PlanError, SceneError};

/// An error of `hplan`, printed as one line after `hplan: `.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A comma-separated value with the wrong number of numbers.
    #[error("expected {expected}, got `{text}`")]
    Numbers {
        /// The value as given.
        text: String,
        /// What was expected (`X,Y`).
        expected: &'static str,
    },
    /// A number of a comma-separated value that does not parse or is not finite.
    #[error("`{part}` is not a finite number (in `{text}`, expected {expected})")]
    NotFinite {
        /// The offending number's text.
        part: String,
        /// The whole value.
        text: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A `--start` of the wrong dimension for the scene or map.
    #[error("--start {start}: expected {expected}")]
    StartShape {
        /// The start as given.
        start: String,
        /// What this input takes (`X,Y,Z on a volume scene`).
        expected: &'static str,
    },
    /// A numeric option out of its range.
    #[error("{option} must {requirement}, got {value}")]
    OutOfRange {
        /// The option (`--max-area`).
        option: &'static str,
        /// What it must be (`be a positive number`, `lie in [0, 1]`).
        requirement: &'static str,
        /// The value given.
        value: f64,
    },
    /// Options that do not go together, or a command without what it needs; the text says
    /// which and what to give instead.
    #[error("{0}")]
    Usage(&'static str),
    /// A command that needs a plane scene was given another kind.
    #[error("{command} works on plane scenes, not {kind}")]
    NotPlane {
        /// The command.
        command: &'static str,
        /// What it was given (`volumes`, `on polygon or arm robots`).
        kind: &'static str,
    },
    /// An input given without the starts it needs.
    #[error("{input} needs at least one --start X,Y")]
    NoStart {
        /// The input (`--poly`).
        input: &'static str,
    },
    /// An error about one input file.
    #[error("{}: {source}", path.display())]
    InFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        #[source]
        source: Box<CliError>,
    },
    /// A scenario of a MovingAI `.scen` file that does not fit its map.
    #[error("{}: scenario {scenario}: {source}", path.display())]
    Scenario {
        /// The `.scen` file.
        path: PathBuf,
        /// The scenario, counted from 1.
        scenario: usize,
        /// What is wrong.
        #[source]
        source: MovingAiError,
    },
    /// Every goal of a several-goal map plan was refused.
    #[error("{}", refused.iter().map(|(k, e)| format!("goal {k}: {e}")).collect::<Vec<_>>().join("; "))]
    GoalsRefused {
        /// Each goal's index and why it was refused.
        refused: Vec<(usize, MapError)>,
    },
    /// A start of the wrong dimension for the scene.
    #[error(transparent)]
    Start(#[from] harmonic_planner::StartError),
    /// A mesh and potential that cannot be written as VTK.
    #[error(transparent)]
    Vtu(#[from] harmonic_planner::VtuError),
    /// A scene file that does not read.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A planner (plane, volume or configuration space) could not be built or run.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A volume mesh could not be written.
    #[error(transparent)]
    VolumeMesh(#[from] harmonic_planner::volume::VolumeError),
    /// An occupancy map that does not load.
    #[error(transparent)]
    Map(#[from] MapError),
    /// A MovingAI map or scenario file that does not load.
    #[error(transparent)]
    MovingAi(#[from] MovingAiError),
    /// A report that does not serialise.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// An output file that cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Standard output cannot be written.
    #[error("cannot write to standard output: {0}")]
    Stdout(#[source] std::io::Error),
}

impl CliError {
    /// `error`, said of the file `path`.
    pub fn in_file(path: &std::path::Path, error: impl Into<CliError>) -> CliError {
        CliError::InFile {
            path: path.to_path_buf(),
            source: Box::new(error.into()),
        }
    }
}

//! `hplan`: plan robot paths through a scene with a harmonic potential.
//!
//! ```text
//! hplan plan SCENE.json [--json] [--svg OUT.svg] [--start X,Y]...
//! hplan plan --map MAP.yaml --goal X,Y [--robot-radius R] [--mesher traced|quadtree] [--start X,Y]... [--json] [--svg OUT.svg]
//! hplan plan (SCENE.json | --map MAP.yaml) --goal X,Y [--start X,Y]... --goal X,Y [--start X,Y]...
//! hplan plan --poly FILE.poly --goal X,Y --start X,Y...
//! hplan plan --mesh-in (BASE | FILE.msh) (--goal-tag TAG | --goal X,Y) --start X,Y...
//! hplan car  SCENE.json --pose X,Y,THETA [--wheelbase L] [--max-steer DEG] [--json] [--svg OUT.svg]
//! hplan export SCENE.json --potential OUT.json
//! ```

#![forbid(unsafe_code)]
// A command's error is made once, on the way out: its size costs nothing worth boxing for.
#![allow(clippy::result_large_err)]

use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod error;
mod progress;

use clap::{ArgGroup, ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use error::CliError;
use harmonic_planner::inputs::{MeshGoal, PolyScene, mesh_planner, read_mesh};
use harmonic_planner::map::{MapMesher, MapOptions, OccupancyMap, movingai};
use harmonic_planner::{
    AnyPlanner, AnyScene, CarParams, PlanReport, Planner, PlannerOptions, Point, Scene, Summary,
    SvgOptions, Workspace,
};

#[derive(Parser)]
#[command(
    name = "hplan",
    version,
    about = "Plan robot paths with harmonic potentials solved by finite elements",
    long_about = "Plan robot paths with harmonic potentials solved by finite elements.\n\n\
        A scene (JSON: workspace polygon, obstacles, goal, boundary conditions) is meshed,\n\
        Laplace's equation is solved on the mesh, and paths follow the potential downhill\n\
        to the goal. A harmonic potential has no local minima, so no path gets stuck.\n\n\
        Example:  hplan plan meshes/reference.json --svg reference.svg"
)]
struct Cli {
    /// Threads for every stage (default: all cores, or `RAYON_NUM_THREADS`); the paths are
    /// the same at any count.
    #[arg(long, global = true, value_name = "N")]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

/// `hplan plan --map --mesher`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum MesherArg {
    Auto,
    Traced,
    Quadtree,
}

impl From<MesherArg> for MapMesher {
    fn from(m: MesherArg) -> MapMesher {
        match m {
            MesherArg::Auto => MapMesher::Auto,
            MesherArg::Quadtree => MapMesher::Quadtree,
            MesherArg::Traced => MapMesher::Traced,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Plan paths from start points to the goal.
    #[command(group(ArgGroup::new("input").required(true).args(["scene", "map", "poly", "mesh_in"])))]
    Plan {
        #[command(flatten)]
        common: Common,
        /// A start point (repeatable; X,Y,Z on a volume scene); defaults to the scene's "starts".
        #[arg(long = "start", value_name = "X,Y", value_parser = parse_start, allow_hyphen_values = true)]
        starts: Vec<Vec<f64>>,
        /// Plan on a ROS map_server occupancy map (YAML + PGM/PNG) instead of a scene file;
        /// unknown cells are obstacles.
        #[arg(
            long,
            value_name = "MAP.yaml",
            conflicts_with = "scene",
            requires = "goal"
        )]
        map: Option<PathBuf>,
        /// The goal (on a map: in its world coordinates; on a scene file it replaces the
        /// scene's goal). Repeat it for several goals on one mesh and one factorisation: each
        /// goal's starts are the --start options after it (those before the first --goal go
        /// to every goal). On a map X,Y,THETA is a pose goal: every path gets `poses`
        /// [x, y, θ] (headings along the path) whose last carries THETA.
        #[arg(long, value_name = "X,Y[,THETA]", value_parser = parse_goal, allow_hyphen_values = true)]
        goal: Vec<Vec<f64>>,
        /// Radius of a disc robot on the map.
        #[arg(long, value_name = "R", default_value_t = 0.0, requires = "map")]
        robot_radius: f64,
        /// On a map: how to mesh it, a speed choice. `auto` (default): `traced` where its
        /// margin changes nothing a path needs, else `quadtree`; `traced`: the robot's clear
        /// cells, with a tracing margin of about a cell, traced to polygons and meshed by
        /// Delaunay refinement (fastest; the margin closes passages narrower than about
        /// three cells); `quadtree`: the clear cells themselves (no margin), by a balanced
        /// quadtree, complete on every map. Either way the radius is kept exactly.
        #[arg(long, value_enum, default_value_t = MesherArg::Auto, requires = "map")]
        mesher: MesherArg,
        /// On a map with graded costs (a `scale` or `raw` map_server YAML): how much they
        /// shape the field. A cell of cost c (1–252) conducts 1/(1 + W·0.016·c) of a free
        /// cell's flow, so paths go around costly cells (W = 1: the costliest cell resists 5×
        /// a free one, as in NavFn), and the costliest cells also absorb, as a thin soft wall,
        /// so walls keep their pull behind a costly band; 0 plans them as free cells.
        #[arg(long, value_name = "W", default_value_t = 1.0, requires = "map")]
        cost_weight: f64,
        /// On a MovingAI `.map` file: metres per cell.
        #[arg(long, value_name = "M", default_value_t = 1.0, requires = "map")]
        resolution: f64,
        /// Plan in a Triangle .poly file's free space (its outer boundary the workspace, the
        /// regions around its hole points obstacles, its other segments mesh constraints);
        /// needs --goal X,Y.
        #[arg(long, value_name = "FILE.poly", conflicts_with_all = ["scene", "map"], requires = "goal")]
        poly: Option<PathBuf>,
        /// Plan on a mesh made elsewhere, as it is: Triangle's BASE.node + BASE.ele (boundary
        /// markers from BASE.poly or BASE.edge if present), or a gmsh FILE.msh (format 4.1,
        /// ASCII or binary); the goal by --goal-tag or --goal X,Y.
        #[arg(long, value_name = "BASE|FILE.msh", conflicts_with_all = ["scene", "map", "poly"])]
        mesh_in: Option<PathBuf>,
        /// With --mesh-in: the goal is the boundary edges of this marker or physical group
        /// (a number, or a gmsh physical name), held at φ = 0; all other boundary edges at 1.
        #[arg(
            long,
            value_name = "NAME|NUMBER",
            requires = "mesh_in",
            conflicts_with = "goal"
        )]
        goal_tag: Option<String>,
        /// On a plane scene with one goal: mesh at 4^K times the largest triangle area,
        /// refine that mesh uniformly K times and solve by multigrid-preconditioned
        /// conjugate gradients, checked (no negative ψ, no underflow, no interior extremum), else
        /// solved directly on the same mesh; 0: the direct solve on the scene's own mesh.
        /// Without it, K = 2 from 100 000 estimated triangles and 0 below.
        #[arg(
            long,
            value_name = "K",
            value_parser = clap::value_parser!(u8).range(0..=8),
            conflicts_with_all = ["map", "poly", "mesh_in"]
        )]
        multigrid: Option<u8>,
    },
    /// Drive a car-like robot (front-wheel steering) along the potential.
    Car {
        #[command(flatten)]
        common: Common,
        /// Start pose: rear-axle midpoint and heading in radians.
        #[arg(long, value_name = "X,Y,THETA", value_parser = parse_pose, allow_hyphen_values = true)]
        pose: Vec<[f64; 3]>,
        /// Distance between the rear and the front axle.
        #[arg(long, value_name = "L", allow_negative_numbers = true)]
        wheelbase: Option<f64>,
        /// Steering limit of the front wheels, in degrees.
        #[arg(
            long,
            value_name = "DEG",
            default_value_t = 35.0,
            allow_negative_numbers = true
        )]
        max_steer: f64,
    },
    /// Run every scenario of a MovingAI `.scen` file (version 1) on its `.map` (a point
    /// robot unless --robot-radius, 1 m cells unless --resolution): per bucket, solved / attempted, the path length
    /// over the file's optimal length (median, worst), and times.
    Bench {
        /// The scenario file; each line's map is looked for beside it.
        scen: PathBuf,
        /// The map, if not the one the scenarios name (beside the .scen file).
        #[arg(long, value_name = "FILE.map")]
        map: Option<PathBuf>,
        /// Metres per cell.
        #[arg(long, value_name = "M", default_value_t = 1.0)]
        resolution: f64,
        /// Radius of a disc robot (default 0: a point).
        #[arg(long, value_name = "R", default_value_t = 0.0)]
        robot_radius: f64,
        /// The mesher (as `plan --mesher`).
        #[arg(long, value_enum, default_value_t = MesherArg::Auto)]
        mesher: MesherArg,
        /// At most this many scenarios (the first ones), 0 for all.
        #[arg(long, value_name = "N", default_value_t = 0)]
        limit: usize,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Write the mesh and the potential for outside tools.
    Export {
        /// The scene file.
        scene: PathBuf,
        /// Write {"vertices","triangles","values","boundary_edges"} to this JSON file.
        #[arg(long, value_name = "OUT.json")]
        potential: Option<PathBuf>,
        /// Write the mesh with φ, ψ and ∇φ for ParaView to this .vtu file.
        #[arg(long, value_name = "OUT.vtu")]
        vtk: Option<PathBuf>,
    },
}

#[derive(Args)]
struct Common {
    /// The scene file (see docs/scene-format.md).
    scene: Option<PathBuf>,
    /// Print one JSON object on stdout instead of a summary.
    #[arg(long)]
    json: bool,
    /// Draw the scene, the potential's isolines and the paths to this SVG file.
    #[arg(long, value_name = "OUT.svg")]
    svg: Option<PathBuf>,
    /// Draw the mesh in the SVG too.
    #[arg(long)]
    mesh: bool,
    /// Write the mesh with φ, ψ and ∇φ for ParaView to this .vtu file.
    #[arg(long, value_name = "OUT.vtu")]
    vtk: Option<PathBuf>,
    /// Override the scene's largest triangle area.
    #[arg(long, value_name = "A")]
    max_area: Option<f64>,
    /// Override a volume scene's largest tetrahedron volume.
    #[arg(long, value_name = "V")]
    max_volume: Option<f64>,
    /// Plan on the ME766 blend k·φ_D + (1 − k)·φ_N (k in [0, 1]; the scene's
    /// `boundary.blend`, see docs/scene-format.md).
    #[arg(long, value_name = "K")]
    blend: Option<f64>,
}

fn parse_numbers<const N: usize>(s: &str, what: &'static str) -> Result<[f64; N], CliError> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(CliError::Numbers {
            text: s.to_string(),
            expected: what,
        });
    }
    let mut out = [0.0; N];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| CliError::NotFinite {
                part: p.to_string(),
                text: s.to_string(),
                expected: what,
            })?;
    }
    Ok(out)
}

/// A start: X,Y on a plane scene, X,Y,Z on a volume (the scene decides which is right).
fn parse_start(s: &str) -> Result<Vec<f64>, CliError> {
    match s.split(',').count() {
        3 => parse_numbers::<3>(s, "X,Y,Z").map(|p| p.to_vec()),
        _ => parse_numbers::<2>(s, "X,Y or X,Y,Z").map(|p| p.to_vec()),
    }
}

/// The starts as points of dimension `N`, or an error naming the first that is not.
fn starts_of<const N: usize>(
    starts: &[Vec<f64>],
    what: &'static str,
) -> Result<Vec<[f64; N]>, CliError> {
    starts
        .iter()
        .map(|s| {
            <[f64; N]>::try_from(s.as_slice()).map_err(|_| {
                let text: Vec<String> = s.iter().map(f64::to_string).collect();
                CliError::StartShape {
                    start: text.join(","),
                    expected: what,
                }
            })
        })
        .collect()
}

/// A goal: X,Y, or on a map X,Y,THETA (a pose goal).
fn parse_goal(s: &str) -> Result<Vec<f64>, CliError> {
    match s.split(',').count() {
        3 => parse_numbers::<3>(s, "X,Y,THETA").map(|p| p.to_vec()),
        _ => parse_numbers::<2>(s, "X,Y or X,Y,THETA").map(|p| p.to_vec()),
    }
}

fn parse_pose(s: &str) -> Result<[f64; 3], CliError> {
    parse_numbers::<3>(s, "X,Y,THETA")
}

fn main() -> ExitCode {
    let parsed = Cli::command()
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m).map(|cli| (cli, m)));
    let (cli, matches) = match parsed {
        Ok(parsed) => parsed,
        Err(e) if !e.use_stderr() => {
            // --help and --version: clap prints them as usual.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("hplan: {}", one_line(&e.render().to_string()));
            return ExitCode::from(2);
        }
    };
    let order = ArgOrder::of(&matches);
    if let Some(n) = cli.threads {
        if n == 0 {
            eprintln!("hplan: --threads must be at least 1");
            return ExitCode::from(2);
        }
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
        {
            eprintln!("hplan: cannot start {n} threads: {e}");
            return ExitCode::FAILURE;
        }
    }
    match run(cli, &order) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("hplan: {message}");
            ExitCode::FAILURE
        }
    }
}

/// A clap error as one line: the message and its notes, without the usage block. A line
/// ending in a colon runs on into the next (`not provided: --goal <X,Y>`); other lines are
/// joined with `; `.
fn one_line(rendered: &str) -> String {
    let parts = rendered
        .lines()
        .take_while(|l| !l.starts_with("Usage:"))
        .map(|l| l.trim().trim_start_matches("error: "))
        .filter(|l| !l.is_empty() && !l.starts_with("For more information"));
    let mut line = String::new();
    for part in parts {
        if !line.is_empty() {
            line.push_str(if line.ends_with(':') { " " } else { "; " });
        }
        line.push_str(part);
    }
    line
}

/// Writes `text` to standard output. A reader that has gone away (`hplan … | head`) ends the
/// output quietly, as for any Unix filter; other write errors are reported.
fn print_out(text: &str) -> Result<(), CliError> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(CliError::Stdout(e)),
    }
}

fn load(path: &Path, common: &Common) -> Result<AnyScene, CliError> {
    let positive = |flag: &'static str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(CliError::OutOfRange {
                option: flag,
                requirement: "be a positive number",
                value: v,
            })
        }
    };
    let scene = AnyScene::from_file(path).map_err(|e| match e {
        // A file that cannot be read is named by the error itself.
        e @ harmonic_planner::SceneError::Io { .. } => CliError::from(e),
        e => CliError::in_file(path, e),
    })?;
    match scene {
        AnyScene::Plane(mut scene) => {
            if common.max_volume.is_some() {
                return Err(CliError::Usage(
                    "--max-volume is for volume scenes; use --max-area",
                ));
            }
            if let Some(a) = common.max_area {
                scene.mesh.max_area = Some(positive("--max-area", a)?);
            }
            if let Some(k) = common.blend {
                if !(0.0..=1.0).contains(&k) {
                    return Err(CliError::OutOfRange {
                        option: "--blend",
                        requirement: "lie in [0, 1]",
                        value: k,
                    });
                }
                let neumann = scene.boundary.blend.map_or(1.0, |b| b.neumann);
                scene.boundary.blend = Some(harmonic_planner::scene::BlendSpec { k, neumann });
            }
            Ok(AnyScene::Plane(scene))
        }
        AnyScene::Volume(mut scene) => {
            if common.max_area.is_some() {
                return Err(CliError::Usage(
                    "--max-area is for plane scenes; use --max-volume",
                ));
            }
            if common.blend.is_some() {
                return Err(CliError::Usage("--blend is for plane scenes"));
            }
            if let Some(v) = common.max_volume {
                scene.mesh.max_volume = Some(positive("--max-volume", v)?);
            }
            Ok(AnyScene::Volume(scene))
        }
        AnyScene::Config(scene) => {
            if common.max_area.is_some() || common.max_volume.is_some() {
                return Err(CliError::Usage(
                    "--max-area and --max-volume are for plane and volume scenes; a polygon or arm robot's scene sets mesh.spacing",
                ));
            }
            Ok(AnyScene::Config(scene))
        }
    }
}

/// The plane scene of `scene`, or an error saying `command` needs one.
fn plane(scene: AnyScene, command: &'static str) -> Result<Scene, CliError> {
    match scene {
        AnyScene::Plane(scene) => Ok(*scene),
        AnyScene::Volume(_) => Err(CliError::NotPlane {
            command,
            kind: "volumes",
        }),
        AnyScene::Config(_) => Err(CliError::NotPlane {
            command,
            kind: "on polygon or arm robots",
        }),
    }
}

/// `hplan plan` on a scene file of any kind: a plane, a volume, a polygon or arm robot.
fn plan_scene(
    scene: &AnyScene,
    path: &Path,
    common: &Common,
    starts: &[Vec<f64>],
    multigrid: Option<u8>,
) -> Result<(), CliError> {
    let starts = if starts.is_empty() {
        scene.starts()
    } else {
        starts.to_vec()
    };
    scene.check_starts(&starts)?;
    let opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        multigrid: multigrid.map(usize::from),
        ..PlannerOptions::default()
    };
    let planner = AnyPlanner::new(scene, &opts).map_err(|e| CliError::in_file(path, e))?;
    let title = match scene {
        AnyScene::Config(s) => s.name.clone(),
        _ => None,
    };
    report_any(&planner, &starts, common, title)
}

/// The one output of `hplan plan` for one goal: the report as JSON or text, `--svg` and
/// `--vtk`, whatever the planner.
fn report_any(
    planner: &AnyPlanner,
    starts: &[Vec<f64>],
    common: &Common,
    title: Option<String>,
) -> Result<(), CliError> {
    let report = planner.report(starts)?;
    if let Some(svg) = &common.svg {
        let opts = SvgOptions {
            show_mesh: common.mesh,
            title,
            ..SvgOptions::default()
        };
        write_file(svg, &planner.svg(&report, &opts))?;
    }
    if let Some(vtk) = &common.vtk {
        write_file(vtk, &planner.vtu()?)?;
    }
    if common.json {
        let json = serde_json::to_string(&report)?;
        print_out(&format!("{json}\n"))
    } else {
        print_out(&report.summary())
    }
}

/// `hplan plan --map` with several goals: a planner per goal, each as complete as one goal's,
/// and each goal on its own: a goal that is refused reports its error in its entry and fails
/// none of the others. The call fails only when every goal is refused.
fn plan_map_goals(
    map: &OccupancyMap,
    headings: &Headings,
    robot_radius: f64,
    opts: &MapOptions,
    common: &Common,
    goals: &[(Point, Vec<[f64; 2]>)],
) -> Result<(), CliError> {
    let planner_opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        ..PlannerOptions::default()
    };
    let mut entries = Vec::new();
    let mut text = String::new();
    let mut drawn: Option<(Planner, Vec<Vec<[f64; 2]>>)> = None;
    let mut refused = Vec::new();
    for (k, (goal, starts)) in goals.iter().enumerate() {
        let at = [goal.x, goal.y];
        match map.planner(at, robot_radius, opts, &planner_opts) {
            Ok(planner) => {
                let report = planner.plan_report(starts);
                let mut entry = match headings.wanted() {
                    true => headings.report_json(&report, at)?,
                    false => serde_json::to_value(&report)?,
                };
                entry["goal"] = serde_json::json!(at);
                entries.push(entry);
                text += &format!("goal {k} ({}, {}):\n{}", at[0], at[1], report.summary());
                if headings.wanted() {
                    text += &headings.end_poses(&report, at);
                }
                let paths = report.paths.iter().map(|p| p.points.clone());
                match &mut drawn {
                    Some((_, all)) => all.extend(paths),
                    None => drawn = Some((planner, paths.collect())),
                }
            }
            Err(e) => {
                entries.push(serde_json::json!({"goal": at, "error": e.to_string(), "paths": []}));
                text += &format!("goal {k} ({}, {}): refused: {e}\n", at[0], at[1]);
                refused.push((k, e));
            }
        }
    }
    if refused.len() == goals.len() {
        return Err(CliError::GoalsRefused { refused });
    }
    if let (Some(svg), Some((planner, paths))) = (&common.svg, &drawn) {
        let opts = SvgOptions {
            show_mesh: common.mesh,
            title: Some(format!(
                "{} goals; isolines of the first planned goal's potential",
                goals.len()
            )),
            ..SvgOptions::default()
        };
        write_file(svg, &planner.svg(paths, &[], &opts))?;
    }
    if let (Some(vtk), Some((planner, _))) = (&common.vtk, &drawn) {
        write_file(vtk, &planner.vtu())?;
    }
    if common.json {
        let json = serde_json::to_string(&serde_json::json!({ "goals": entries }))?;
        print_out(&format!("{json}\n"))
    } else {
        print_out(&text)
    }
}

/// `hplan plan --map` with one goal: the map's own planner ([`OccupancyMap::planner`]).
fn plan_map(
    map: &OccupancyMap,
    goal: [f64; 2],
    headings: &Headings,
    robot_radius: f64,
    opts: &MapOptions,
    common: &Common,
    starts: &[[f64; 2]],
) -> Result<(), CliError> {
    let planner_opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        ..PlannerOptions::default()
    };
    let planner = map.planner(goal, robot_radius, opts, &planner_opts)?;
    let report = planner.plan_report(starts);
    draw_shaded(&planner, &report, common, map.cost_shading())?;
    if !headings.wanted() {
        return if common.json {
            let json = serde_json::to_string(&report)?;
            print_out(&format!("{json}\n"))
        } else {
            print_out(&report.summary())
        };
    }
    if common.json {
        let json = headings.report_json(&report, goal)?;
        print_out(&format!("{json}\n"))
    } else {
        print_out(&(report.summary() + &headings.end_poses(&report, goal)))
    }
}

/// The headings of `hplan plan --map` with pose goals (`--goal X,Y,THETA`) or pose starts
/// (`--start X,Y,THETA`): when there are any, paths are given as poses too.
#[derive(Default)]
struct Headings {
    /// Each pose goal's heading, by its point's bits.
    goals: std::collections::HashMap<[u64; 2], f64>,
    /// Each pose start's heading, by its point's bits.
    starts: std::collections::HashMap<[u64; 2], f64>,
}

impl Headings {
    fn key(p: [f64; 2]) -> [u64; 2] {
        [p[0].to_bits(), p[1].to_bits()]
    }

    /// The starts as points, with the headings of goals and starts given as poses.
    fn of(goals: &[Vec<f64>], starts: &[Vec<f64>]) -> Result<(Headings, Vec<[f64; 2]>), CliError> {
        let mut h = Headings::default();
        for g in goals {
            if let [x, y, theta] = g[..] {
                h.goals.insert(Self::key([x, y]), theta);
            }
        }
        let mut points = Vec::with_capacity(starts.len());
        for s in starts {
            match s[..] {
                [x, y] => points.push([x, y]),
                [x, y, theta] => {
                    h.starts.insert(Self::key([x, y]), theta);
                    points.push([x, y]);
                }
                _ => {
                    let text: Vec<String> = s.iter().map(f64::to_string).collect();
                    return Err(CliError::StartShape {
                        start: text.join(","),
                        expected: "X,Y or X,Y,THETA on a map",
                    });
                }
            }
        }
        Ok((h, points))
    }

    fn wanted(&self) -> bool {
        !(self.goals.is_empty() && self.starts.is_empty())
    }

    fn poses(&self, path: &harmonic_planner::PlannedPath, goal: [f64; 2]) -> Vec<[f64; 3]> {
        let start = self.starts.get(&Self::key(path.start)).copied();
        path.poses(start, self.goals.get(&Self::key(goal)).copied())
    }

    /// A map report's JSON with each path's `poses`.
    fn report_json(
        &self,
        report: &PlanReport,
        goal: [f64; 2],
    ) -> Result<serde_json::Value, CliError> {
        let mut json = serde_json::to_value(report)?;
        for (k, path) in report.paths.iter().enumerate() {
            json["paths"][k]["poses"] = serde_json::json!(self.poses(path, goal));
        }
        Ok(json)
    }

    /// A line per path with its last pose, for the summary.
    fn end_poses(&self, report: &PlanReport, goal: [f64; 2]) -> String {
        report
            .paths
            .iter()
            .filter_map(|p| self.poses(p, goal).last().copied())
            .map(|[x, y, t]| format!("  ends at ({x:.3}, {y:.3}), heading {t:.4}\n"))
            .collect()
    }
}

/// The SVG and VTU files a plan report asks for.
/// `draw`, with regions shaded under the picture (a map's graded costs).
fn draw_shaded(
    planner: &Planner,
    report: &PlanReport,
    common: &Common,
    shaded: Vec<(Vec<[f64; 2]>, f64)>,
) -> Result<(), CliError> {
    if let Some(svg) = &common.svg {
        let paths: Vec<_> = report.paths.iter().map(|p| p.points.clone()).collect();
        let opts = SvgOptions {
            show_mesh: common.mesh,
            shaded,
            ..SvgOptions::default()
        };
        write_file(svg, &planner.svg(&paths, &[], &opts))?;
    }
    if let Some(vtk) = &common.vtk {
        write_file(vtk, &planner.vtu())?;
    }
    Ok(())
}

/// A map_server YAML (and its image), or a MovingAI `.map` of `resolution` metres per cell.
fn load_map(path: &Path, resolution: f64) -> Result<OccupancyMap, CliError> {
    if path.extension().is_some_and(|e| e == "map") {
        Ok(movingai::load_map(path, resolution)?)
    } else {
        Ok(OccupancyMap::load(path)?)
    }
}

/// One bucket's figures in `hplan bench`.
struct BenchBucket {
    bucket: u32,
    attempted: usize,
    solved: usize,
    ratio_median: f64,
    ratio_worst: f64,
    build_ms_median: f64,
    query_ms_median: f64,
    whole_s: f64,
}

/// `hplan bench FILE.scen`: every scenario planned from a fresh planner towards its goal.
fn bench(
    scen: &Path,
    map: Option<&Path>,
    resolution: f64,
    robot_radius: f64,
    mesher: MapMesher,
    limit: usize,
    json: bool,
) -> Result<(), CliError> {
    let mut scenarios = movingai::load_scen(scen)?;
    if limit > 0 {
        scenarios.truncate(limit);
    }
    let dir = scen.parent().unwrap_or(Path::new("."));
    let mut maps: std::collections::HashMap<PathBuf, OccupancyMap> = Default::default();
    let opts = MapOptions {
        mesher,
        ..MapOptions::default()
    };
    let planner_opts = PlannerOptions::default();
    // Per bucket: (attempted, solved, ratios, build ms, query ms, whole s).
    type Rows = (usize, usize, Vec<f64>, Vec<f64>, Vec<f64>, f64);
    let mut buckets: std::collections::BTreeMap<u32, Rows> = Default::default();
    for (k, s) in scenarios.iter().enumerate() {
        let file = match map {
            Some(m) => m.to_path_buf(),
            None => {
                let named = dir.join(&s.map);
                let base = Path::new(&s.map).file_name().map(|b| dir.join(b));
                match base {
                    Some(b) if !named.exists() && b.exists() => b,
                    _ => named,
                }
            }
        };
        if !maps.contains_key(&file) {
            let m = movingai::load_map(&file, resolution)?;
            maps.insert(file.clone(), m);
        }
        let grid = &maps[&file];
        s.check_against(grid).map_err(|source| CliError::Scenario {
            path: scen.to_path_buf(),
            scenario: k + 1,
            source,
        })?;
        let goal = grid.cell_center(s.goal.0, s.goal.1);
        let start = grid.cell_center(s.start.0, s.start.1);
        let t = std::time::Instant::now();
        let planner = grid.planner(goal, robot_radius, &opts, &planner_opts);
        let build = t.elapsed().as_secs_f64() * 1e3;
        let t = std::time::Instant::now();
        let path = planner.as_ref().ok().map(|p| p.plan(start));
        let query = t.elapsed().as_secs_f64() * 1e3;
        let row = buckets.entry(s.bucket).or_default();
        row.0 += 1;
        row.5 += (build + query) / 1e3;
        row.3.push(build);
        let Some(path) = path else {
            if let Err(e) = &planner {
                eprintln!("{}: scenario {}: {e}", scen.display(), k + 1);
            }
            continue;
        };
        row.4.push(query);
        let ends = path
            .points
            .last()
            .is_some_and(|p| (p[0] - goal[0]).hypot(p[1] - goal[1]) <= 1e-9);
        if path.status.reached_goal() && ends {
            row.1 += 1;
            if s.optimal > 0.0 {
                row.2.push(path.length / resolution / s.optimal);
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    // Every scenario's ratio, build and query time, for the line under the buckets.
    let mut all: (Vec<f64>, Vec<f64>, Vec<f64>) = Default::default();
    for (_, _, r, b, q, _) in buckets.values() {
        all.0.extend(r);
        all.1.extend(b);
        all.2.extend(q);
    }
    let rows: Vec<BenchBucket> = buckets
        .into_iter()
        .map(
            |(bucket, (attempted, solved, mut r, mut b, mut q, whole_s))| BenchBucket {
                bucket,
                attempted,
                solved,
                ratio_worst: r.iter().copied().fold(f64::NAN, f64::max),
                ratio_median: median(&mut r),
                build_ms_median: median(&mut b),
                query_ms_median: median(&mut q),
                whole_s,
            },
        )
        .collect();
    if json {
        let buckets: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "bucket": r.bucket,
                    "attempted": r.attempted,
                    "solved": r.solved,
                    "ratio_median": r.ratio_median,
                    "ratio_worst": r.ratio_worst,
                    "build_ms_median": r.build_ms_median,
                    "query_ms_median": r.query_ms_median,
                    "whole_s": r.whole_s,
                })
            })
            .collect();
        let text = serde_json::to_string(&serde_json::json!({
            "scen": scen.display().to_string(),
            "buckets": buckets,
        }))?;
        return print_out(&format!("{text}\n"));
    }
    let mut out = format!(
        "{}: {} scenarios\nbucket  solved  length/optimal median  worst  build ms  query ms  whole s\n",
        scen.display(),
        scenarios.len()
    );
    for r in &rows {
        out += &format!(
            "{:>6}  {:>3}/{:<3} {:>21.3}  {:>5.3}  {:>8.2}  {:>8.3}  {:>7.3}\n",
            r.bucket,
            r.solved,
            r.attempted,
            r.ratio_median,
            r.ratio_worst,
            r.build_ms_median,
            r.query_ms_median,
            r.whole_s
        );
    }
    let (solved, attempted) = rows
        .iter()
        .fold((0, 0), |a, r| (a.0 + r.solved, a.1 + r.attempted));
    let whole: f64 = rows.iter().map(|r| r.whole_s).sum();
    out += &format!(
        "   all  {solved:>3}/{attempted:<3} {:>21.3}  {:>5.3}  {:>8.2}  {:>8.3}  {whole:>7.3}\n",
        median(&mut all.0),
        all.0.iter().copied().fold(f64::NAN, f64::max),
        median(&mut all.1),
        median(&mut all.2),
    );
    print_out(&out)
}

fn write_file(path: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(path, text).map_err(|source| CliError::Write {
        path: path.to_path_buf(),
        source,
    })
}

fn build(
    scene: &Scene,
    path: &Path,
    quiet: bool,
    multigrid: Option<u8>,
) -> Result<Planner, CliError> {
    let opts = PlannerOptions {
        on_stage: progress::spinner(quiet),
        multigrid: multigrid.map(usize::from),
        ..PlannerOptions::default()
    };
    Planner::with_options(scene, &opts).map_err(|e| CliError::in_file(path, e))
}

/// Where each `--goal` and `--start` of `hplan plan` stood on the command line, so each
/// goal gets the starts that follow it.
#[derive(Default)]
struct ArgOrder {
    goals: Vec<usize>,
    starts: Vec<usize>,
}

impl ArgOrder {
    fn of(matches: &ArgMatches) -> ArgOrder {
        let Some(plan) = matches.subcommand_matches("plan") else {
            return ArgOrder::default();
        };
        let at = |id: &str| {
            plan.indices_of(id)
                .map(|i| i.collect::<Vec<_>>())
                .unwrap_or_default()
        };
        ArgOrder {
            goals: at("goal"),
            starts: at("starts"),
        }
    }

    /// Each goal with its starts: those after it (before the next goal), plus those before
    /// the first goal; `default` when a goal gets none.
    fn starts_per_goal(
        &self,
        goals: &[[f64; 2]],
        starts: &[[f64; 2]],
        default: &[[f64; 2]],
    ) -> Vec<(Point, Vec<[f64; 2]>)> {
        let owner = |k: usize| {
            let at = self.starts.get(k).copied().unwrap_or(0);
            self.goals.iter().rposition(|&g| g < at)
        };
        goals
            .iter()
            .enumerate()
            .map(|(j, g)| {
                let mut own: Vec<[f64; 2]> = starts
                    .iter()
                    .enumerate()
                    .filter(|&(k, _)| owner(k).is_none_or(|o| o == j))
                    .map(|(_, &s)| s)
                    .collect();
                if own.is_empty() {
                    own = default.to_vec();
                }
                (Point::new(g[0], g[1]), own)
            })
            .collect()
    }
}

/// The starts of `--poly` and `--mesh-in` (they have no scene to take defaults from).
fn given_starts(starts: &[Vec<f64>], input: &'static str) -> Result<Vec<[f64; 2]>, CliError> {
    let starts = starts_of::<2>(starts, "X,Y")?;
    if starts.is_empty() {
        return Err(CliError::NoStart { input });
    }
    Ok(starts)
}

/// Plans from `starts` on `planner` and writes what `common` asks for.
fn report_plan(planner: Planner, starts: &[[f64; 2]], common: &Common) -> Result<(), CliError> {
    let starts: Vec<Vec<f64>> = starts.iter().map(|s| s.to_vec()).collect();
    report_any(&AnyPlanner::Plane(Box::new(planner)), &starts, common, None)
}

/// `hplan plan --poly FILE.poly --goal X,Y --start X,Y...`.
fn plan_poly(
    path: &Path,
    common: &Common,
    goal: &[[f64; 2]],
    starts: &[Vec<f64>],
) -> Result<(), CliError> {
    let [goal] = goal else {
        return Err(CliError::Usage("--poly takes one --goal X,Y"));
    };
    if common.max_volume.is_some() || common.blend.is_some() {
        return Err(CliError::Usage(
            "--max-volume and --blend are not for --poly",
        ));
    }
    let starts = given_starts(starts, "--poly")?;
    let mut poly = PolyScene::read(path, *goal)?;
    if let Some(a) = common.max_area {
        if !(a.is_finite() && a > 0.0) {
            return Err(CliError::OutOfRange {
                option: "--max-area",
                requirement: "be a positive number",
                value: a,
            });
        }
        poly.scene.mesh.max_area = Some(a);
    }
    let opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        ..Default::default()
    };
    let planner = poly
        .planner(&opts)
        .map_err(|e| CliError::in_file(path, e))?;
    report_plan(planner, &starts, common)
}

/// `hplan plan --mesh-in (BASE | FILE.msh) (--goal-tag TAG | --goal X,Y) --start X,Y...`.
fn plan_mesh_in(
    path: &Path,
    common: &Common,
    goal: &[[f64; 2]],
    goal_tag: Option<&str>,
    starts: &[Vec<f64>],
) -> Result<(), CliError> {
    if common.max_area.is_some() || common.max_volume.is_some() || common.blend.is_some() {
        return Err(CliError::Usage(
            "--max-area, --max-volume and --blend are not for --mesh-in (the mesh is planned on as it is)",
        ));
    }
    let goal = match (goal_tag, goal) {
        (Some(tag), []) => MeshGoal::Tag(tag.to_string()),
        (None, [p]) => MeshGoal::Point(*p),
        _ => {
            return Err(CliError::Usage(
                "--mesh-in takes one goal: --goal-tag NAME|NUMBER or --goal X,Y",
            ));
        }
    };
    let starts = given_starts(starts, "--mesh-in")?;
    let mesh = read_mesh(path)?;
    let opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        ..Default::default()
    };
    let planner = mesh_planner(&mesh, &goal, &opts).map_err(|e| match e {
        // Errors about the file name it already.
        e @ harmonic_planner::PlanError::Mesh(_) => CliError::from(e),
        e => CliError::in_file(path, e),
    })?;
    report_plan(planner, &starts, common)
}

/// `hplan plan SCENE` with several goals: one workspace, one factorisation, one result per
/// goal.
fn plan_goals(
    scene: &Scene,
    path: &Path,
    common: &Common,
    goals: &[(Point, Vec<[f64; 2]>)],
) -> Result<(), CliError> {
    let opts = PlannerOptions {
        on_stage: progress::spinner(common.json),
        ..PlannerOptions::default()
    };
    let workspace =
        Workspace::with_options(scene, &opts).map_err(|e| CliError::in_file(path, e))?;
    let (report, planners) = workspace.report(goals)?;
    if let (Some(svg), Some(first)) = (&common.svg, planners.first()) {
        let paths: Vec<_> = report
            .goals
            .iter()
            .flat_map(|g| g.paths.iter().map(|p| p.points.clone()))
            .collect();
        let opts = SvgOptions {
            show_mesh: common.mesh,
            title: Some(format!(
                "{} goals; isolines of the first goal's potential",
                goals.len()
            )),
            ..SvgOptions::default()
        };
        write_file(svg, &first.svg(&paths, &[], &opts))?;
    }
    if let (Some(vtk), Some(first)) = (&common.vtk, planners.first()) {
        write_file(vtk, &first.vtu())?;
    }
    if common.json {
        let json = serde_json::to_string(&report)?;
        print_out(&format!("{json}\n"))
    } else {
        print_out(&report.summary())
    }
}

fn run(cli: Cli, order: &ArgOrder) -> Result<(), CliError> {
    match cli.command {
        Command::Plan {
            common,
            starts,
            map,
            goal,
            robot_radius,
            mesher,
            cost_weight,
            resolution,
            poly,
            mesh_in,
            goal_tag,
            multigrid,
        } => {
            let pose_goals = goal.clone();
            let goal: Vec<[f64; 2]> = goal.iter().map(|g| [g[0], g[1]]).collect();
            if map.is_none() && pose_goals.iter().any(|g| g.len() == 3) {
                return Err(CliError::Usage(
                    "--goal X,Y,THETA (a pose goal) is for maps; give X,Y",
                ));
            }
            if let Some(poly) = &poly {
                return plan_poly(poly, &common, &goal, &starts);
            }
            if let Some(mesh) = &mesh_in {
                return plan_mesh_in(mesh, &common, &goal, goal_tag.as_deref(), &starts);
            }
            let (mut scene, path) = match (&common.scene, &map, goal.first()) {
                (_, Some(map), Some(&first)) => {
                    let opts = MapOptions {
                        max_area: common.max_area,
                        mesher: mesher.into(),
                        cost_weight,
                        ..MapOptions::default()
                    };
                    let grid = load_map(map, resolution)?;
                    let (headings, all_starts) = Headings::of(&pose_goals, &starts)?;
                    if goal.len() == 1 {
                        return plan_map(
                            &grid,
                            first,
                            &headings,
                            robot_radius,
                            &opts,
                            &common,
                            &all_starts,
                        );
                    }
                    let goals = order.starts_per_goal(&goal, &all_starts, &[]);
                    return plan_map_goals(&grid, &headings, robot_radius, &opts, &common, &goals);
                }
                (Some(path), None, _) => match load(path, &common)? {
                    AnyScene::Plane(scene) => (*scene, path.clone()),
                    _ if multigrid.is_some_and(|k| k > 0) => {
                        return Err(CliError::in_file(
                            path,
                            CliError::Usage(
                                "--multigrid is for plane scenes; this scene is a volume or a polygon or arm robot's",
                            ),
                        ));
                    }
                    scene @ AnyScene::Volume(_) if goal.is_empty() => {
                        return plan_scene(&scene, path, &common, &starts, None);
                    }
                    AnyScene::Volume(_) => {
                        return Err(CliError::in_file(
                            path,
                            CliError::Usage(
                                "--goal X,Y is for plane scenes and maps; a volume scene names its goal",
                            ),
                        ));
                    }
                    scene @ AnyScene::Config(_) if goal.is_empty() => {
                        return plan_scene(&scene, path, &common, &starts, None);
                    }
                    AnyScene::Config(_) => {
                        return Err(CliError::in_file(
                            path,
                            CliError::Usage(
                                "--goal X,Y is for plane scenes and maps; a polygon or arm robot's scene names its goal",
                            ),
                        ));
                    }
                },
                _ => {
                    return Err(CliError::Usage(
                        "plan needs SCENE.json or --map MAP.yaml --goal X,Y",
                    ));
                }
            };
            let all_starts = starts_of::<2>(&starts, "X,Y on a plane scene")?;
            if goal.len() > 1 {
                if multigrid.is_some_and(|k| k > 0) {
                    return Err(CliError::Usage(
                        "--multigrid plans for one goal (several goals share one factorisation, which a multigrid solve does not keep)",
                    ));
                }
                let goals = order.starts_per_goal(&goal, &all_starts, &scene.starts);
                return plan_goals(&scene, &path, &common, &goals);
            }
            if let (Some(&g), None) = (goal.first(), &map) {
                // One goal for a scene file: it replaces the scene's goal(s).
                scene.goal =
                    harmonic_planner::scene::Goals(vec![harmonic_planner::scene::Region {
                        point: Some(g),
                        ..Default::default()
                    }]);
            }
            plan_scene(
                &AnyScene::Plane(Box::new(scene)),
                &path,
                &common,
                &starts,
                multigrid,
            )?;
        }
        Command::Car {
            common,
            pose,
            wheelbase,
            max_steer,
        } => {
            let path = common
                .scene
                .clone()
                .ok_or(CliError::Usage("car needs a SCENE.json"))?;
            let scene = plane(load(&path, &common)?, "car")?;
            if pose.is_empty() {
                return Err(CliError::Usage("car needs at least one --pose X,Y,THETA"));
            }
            let planner = build(&scene, &path, common.json, None)?;
            let mut params = CarParams::for_scene(&planner);
            if let Some(l) = wheelbase {
                params.wheelbase = l;
            }
            params.max_steer = max_steer.to_radians();
            params.validate()?;
            let report = planner.car_report(&pose, &params)?;
            if let Some(svg) = &common.svg {
                let poses: Vec<_> = report.paths.iter().map(|p| p.poses.clone()).collect();
                let opts = SvgOptions {
                    show_mesh: common.mesh,
                    car_size: (params.wheelbase * 1.25, params.wheelbase * 0.6),
                    ..SvgOptions::default()
                };
                write_file(svg, &planner.svg(&[], &poses, &opts))?;
            }
            if let Some(vtk) = &common.vtk {
                write_file(vtk, &planner.vtu())?;
            }
            if common.json {
                let json = serde_json::to_string(&report)?;
                print_out(&format!("{json}\n"))?;
            } else {
                print_out(&report.summary())?;
            }
        }
        Command::Bench {
            scen,
            map,
            resolution,
            robot_radius,
            mesher,
            limit,
            json,
        } => {
            bench(
                &scen,
                map.as_deref(),
                resolution,
                robot_radius,
                mesher.into(),
                limit,
                json,
            )?;
        }
        Command::Export {
            scene: path,
            potential,
            vtk,
        } => {
            if potential.is_none() && vtk.is_none() {
                return Err(CliError::Usage(
                    "export needs --potential OUT.json and/or --vtk OUT.vtu",
                ));
            }
            let no_overrides = Common {
                scene: None,
                json: false,
                svg: None,
                mesh: false,
                vtk: None,
                max_area: None,
                max_volume: None,
                blend: None,
            };
            let scene = load(&path, &no_overrides)?;
            let planner = AnyPlanner::new(&scene, &PlannerOptions::default())
                .map_err(|e| CliError::in_file(&path, e))?;
            if let Some(out) = &potential {
                write_file(out, &serde_json::to_string(&planner.export())?)?;
            }
            if let Some(vtk) = &vtk {
                write_file(vtk, &planner.vtu()?)?;
            }
        }
    }
    Ok(())
}

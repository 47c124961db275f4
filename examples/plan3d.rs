//! Plans a volume scene end to end: parse, mesh (isosurface stuffing), assemble, solve, trace
//! every start with the exact and the smooth tracer; prints sizes, timings (tetrahedra per
//! second meshing), path statuses and lengths, and optionally writes the potential as `.vtu`
//! and the xy/xz/yz projections as SVG.
//!
//! ```text
//! cargo run --release --example plan3d -- meshes/torus3d.json \
//!     [--max-volume V] [--vtu out.vtu] [--svg out.svg]
//! ```

use std::sync::Arc;
use std::time::Instant;

use harmonic_fem::volume::{
    VolumeAssembler, VolumePotential, VolumeSolveMethod, solve_volume,
    solve_volume_potential_with_report,
};
use harmonic_planner::scene::VolumeScene;
use harmonic_trajectory::volume::{ExactVolumeOptions, P1VolumeField, trace_exact_volume};
use harmonic_trajectory::{Locate, SmoothOptions, trace_smooth};
use harmonic_volume::io::{PointData, write_projections_svg, write_vtu};
use harmonic_volume::{MeshOptions, Point, PointClass, quality};

fn main() {
    if let Err(e) = run() {
        eprintln!("plan3d: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut scene = None;
    let (mut vtu, mut svg, mut max_volume) = (None, None, None);
    let mut i = 0;
    while i < args.len() {
        let value = |i: usize| {
            args.get(i + 1)
                .cloned()
                .ok_or_else(|| format!("{} needs a value", args[i]))
        };
        match args[i].as_str() {
            "--vtu" => vtu = Some(value(i)?),
            "--svg" => svg = Some(value(i)?),
            "--max-volume" => max_volume = Some(value(i)?.parse::<f64>()?),
            s if scene.is_none() && !s.starts_with("--") => {
                scene = Some(s.to_string());
                i += 1;
                continue;
            }
            s => return Err(format!("unexpected argument `{s}`").into()),
        }
        i += 2;
    }
    let scene = scene.ok_or("usage: plan3d SCENE.json [--max-volume V] [--vtu OUT] [--svg OUT]")?;
    let text = std::fs::read_to_string(&scene).map_err(|e| format!("{scene}: {e}"))?;
    let spec: VolumeScene = serde_json::from_str(&text).map_err(|e| format!("{scene}: {e}"))?;
    let domain = spec.build()?;
    let max_volume = match max_volume {
        Some(v) => v,
        None => spec.max_volume(&domain)?,
    };

    let t = Instant::now();
    let (mesh, report) = domain.mesh(&MeshOptions::with_max_volume(max_volume))?;
    let mesh_s = t.elapsed().as_secs_f64();
    let q = quality(&mesh);
    println!(
        "{}: {} vertices, {} tetrahedra, {} boundary faces (h = {:.4}, margin {:.2e}, {} pass(es))",
        spec.name.as_deref().unwrap_or(&scene),
        q.vertices,
        q.tetrahedra,
        q.boundary_faces,
        report.spacing,
        report.margin,
        report.passes
    );
    println!(
        "  dihedral angles {:.1}°..{:.1}°, {} of {} edges with negative stiffness weight",
        q.min_dihedral_deg, q.max_dihedral_deg, q.negative_weight_edges, q.edges
    );
    println!(
        "  meshing {:.3} s ({:.0} tetrahedra/s)",
        mesh_s,
        q.tetrahedra as f64 / mesh_s
    );
    let mesh = Arc::new(mesh);
    let bcs = spec.conditions();

    let t = Instant::now();
    let assembler = VolumeAssembler::new(Arc::clone(&mesh), &bcs)?;
    let system = assembler.assemble(&bcs)?;
    let assemble_s = t.elapsed().as_secs_f64();
    let (galerkin, _) = solve_volume(&system, VolumeSolveMethod::Auto)?;
    let galerkin = VolumePotential::new(Arc::clone(&mesh), galerkin, system.reference())?;
    println!(
        "  {} unknowns: assembly {:.3} s; Galerkin stiffness: {} positive off-diagonals, {} interior extrema",
        system.matrix().n(),
        assemble_s,
        system.positive_offdiagonals(),
        galerkin.interior_local_extrema(),
    );
    // The planning solve (Galerkin, or clamped and accurate where that is needed), timed.
    let t = Instant::now();
    let (potential, solve, clamped) = solve_volume_potential_with_report(Arc::clone(&mesh), &bcs)?;
    println!(
        "  planning solve {:.3} s in all (last solve {:.3} s by {:?}{}, clamped stiffness: {clamped}), {} interior extrema, ψ in [{:.3e}, {:.3e}]",
        t.elapsed().as_secs_f64(),
        solve.seconds,
        solve.method,
        if solve.iterations > 0 {
            format!(", {} iterations", solve.iterations)
        } else {
            String::new()
        },
        potential.interior_local_extrema(),
        potential
            .psi()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        potential.psi().iter().copied().fold(0.0, f64::max),
    );

    let goal_radius = report.point_goal_radius;
    let classify = |p: &Point| match domain.classify(p, goal_radius) {
        PointClass::Free => Locate::Inside(0),
        PointClass::Goal(j) => Locate::Goal(j),
        PointClass::Obstacle(_) => Locate::InObstacle,
        PointClass::OutsideWorkspace => Locate::OutsideWorkspace,
    };
    let field = P1VolumeField::ascending(&mesh, potential.psi())?.with_outside(&classify);
    let (lo, hi) = mesh.bounds();
    let smooth_opts = SmoothOptions::for_scale((hi - lo).max());
    let mut paths = Vec::new();
    for s in spec.start_points() {
        let t = Instant::now();
        let exact = trace_exact_volume(&field, s, &ExactVolumeOptions::default());
        let exact_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let smooth = trace_smooth(&field, s, &smooth_opts)?;
        let smooth_s = t.elapsed().as_secs_f64();
        println!(
            "  start ({}, {}, {}): exact {} length {:.4} ({} moves, {:.1} ms), smooth {} length {:.4} ({} steps, {:.1} ms), min |∇φ| {:.3e}",
            s.x,
            s.y,
            s.z,
            exact.status.as_str(),
            exact.length,
            exact.cells_crossed,
            1e3 * exact_s,
            smooth.status.as_str(),
            smooth.length,
            smooth.cells_crossed,
            1e3 * smooth_s,
            exact.min_gradient
        );
        if !exact.status.reached_goal() {
            println!(
                "    exact ended {:?} after {:?}",
                exact.status,
                &exact.points[exact.points.len().saturating_sub(4)..]
            );
        }
        paths.push(exact.points);
    }
    if let Some(path) = vtu {
        let phi = potential.phi_at_vertices();
        let grad: Vec<[f64; 3]> = potential
            .recovered_gradients()
            .iter()
            .map(|g| [-g.x, -g.y, -g.z])
            .collect();
        write_vtu(
            &path,
            &mesh,
            &[
                PointData::Scalar("phi", &phi),
                PointData::Scalar("psi", potential.psi()),
                PointData::Vector("grad_phi", &grad),
            ],
        )?;
        println!("  wrote {path}");
    }
    if let Some(path) = svg {
        write_projections_svg(&path, &mesh, &paths)?;
        println!("  wrote {path}");
    }
    Ok(())
}

//! Solves a scene's potential and prints φ at given points, with the time of each stage —
//! for comparing against outside solvers (FreeFEM, scikit-fem) point by point.
//!
//! ```text
//! cargo run --release --example probe -- meshes/reference.json --max-area 0.0044 --at 1,1 --at 8,3 --json
//! ```
//!
//! `--sequential` orders, factors and solves on one thread ([`Parallelism::Sequential`]); by
//! default the ordering of large systems uses rayon's pool (the factorisation and solves stay
//! on one thread, see `Parallelism`). The mesher's two halves run on two threads of rayon's
//! pool (one after the other in a pool of one).
//!
//! `--multigrid K` meshes at `4^K` times the largest triangle area and refines the mesh
//! uniformly `K` times (the same smallest angle, triangles of at most the area asked), then
//! solves by conjugate gradients preconditioned with a multigrid V-cycle over those levels
//! (`MultilevelSystem`) instead of the direct Cholesky solve. "assemble" is then every
//! level's assembly, "analyze" and "factor" the cycle's set-up (the coarsest level factored).

use std::sync::Arc;
use std::time::Instant;

use harmonic_planner::fem::{
    Assembler, AssemblyOptions, MULTIGRID_REL_TOL, MultigridOptions, MultilevelSystem, Potential,
};
use harmonic_planner::mesh::Domain;
use harmonic_planner::solver::{Parallelism, SymbolicCholesky};
use harmonic_planner::{Point, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().filter(|a| !a.starts_with("--")).ok_or(
        "usage: probe SCENE.json [--max-area A] --at X,Y [--at X,Y ...] [--json] [--sequential] [--multigrid K]",
    )?;
    let mut scene = Scene::from_file(path)?;
    let mut points = Vec::new();
    let mut json = false;
    let mut parallelism = Parallelism::default();
    let mut multigrid: Option<u32> = None;
    let mut i = 1;
    while i < args.len() {
        match args[i].as_str() {
            "--json" => json = true,
            "--sequential" => parallelism = Parallelism::Sequential,
            "--multigrid" => {
                i += 1;
                let k: u32 = args
                    .get(i)
                    .ok_or("--multigrid needs a level count")?
                    .parse()?;
                if !(1..=8).contains(&k) {
                    return Err(format!("--multigrid {k}: give 1 to 8 refinements").into());
                }
                multigrid = Some(k);
            }
            "--max-area" => {
                i += 1;
                scene.mesh.max_area = Some(args.get(i).ok_or("--max-area needs a value")?.parse()?);
            }
            "--at" => {
                i += 1;
                let v = args.get(i).ok_or("--at needs X,Y")?;
                let (x, y) = v
                    .split_once(',')
                    .ok_or_else(|| format!("--at {v}: expected X,Y"))?;
                points.push(Point::new(x.trim().parse()?, y.trim().parse()?));
            }
            other => return Err(format!("unknown argument `{other}`").into()),
        }
        i += 1;
    }

    if let Some(k) = multigrid {
        return probe_multigrid(&scene, k, &points, json);
    }
    let t = Instant::now();
    let opts = scene.mesh_options();
    let (mesh, _) = Domain::new(&scene.domain_spec(), &opts)?.mesh(&opts)?;
    let mesh = Arc::new(mesh);
    let mesh_ms = t.elapsed().as_secs_f64() * 1e3;

    let t = Instant::now();
    let bcs = scene.boundary_conditions();
    let assembler = Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default())?;
    let system = assembler.assemble(&bcs)?;
    let assemble_ms = t.elapsed().as_secs_f64() * 1e3;

    let t = Instant::now();
    let symbolic = SymbolicCholesky::analyze_with(
        system.matrix(),
        assembler.nested_dissection(),
        parallelism,
    )?;
    let analyze_ms = t.elapsed().as_secs_f64() * 1e3;
    let factor = symbolic.factor(system.matrix())?;
    let factor_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let x = factor.solve(system.rhs())?;
    let solve_ms = t.elapsed().as_secs_f64() * 1e3;

    let potential = Potential::new(Arc::clone(&mesh), system.expand(&x)?, system.reference())?;
    let stages = Stages {
        mesh_ms,
        assemble_ms,
        analyze_ms,
        factor_ms,
        solve_ms,
    };
    report(&potential, &points, &stages, None, json)
}

/// Milliseconds per stage; `factor_ms` includes `analyze_ms`.
struct Stages {
    mesh_ms: f64,
    assemble_ms: f64,
    analyze_ms: f64,
    factor_ms: f64,
    solve_ms: f64,
}

/// The `--multigrid K` pipeline: a coarse mesh refined K times, every level assembled, CG
/// with a V-cycle.
fn probe_multigrid(
    scene: &Scene,
    refinements: u32,
    points: &[Point],
    json: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let mut opts = scene.mesh_options();
    opts.max_area = opts.max_area.map(|a| a * 4f64.powi(refinements as i32));
    let (coarse, _) = Domain::new(&scene.domain_spec(), &opts)?.mesh(&opts)?;
    let hierarchy = harmonic_mesh::uniform_hierarchy(coarse, refinements as usize)?;
    let mesh_ms = t.elapsed().as_secs_f64() * 1e3;

    let t = Instant::now();
    let levels = MultilevelSystem::assemble(&hierarchy, &scene.boundary_conditions())?;
    let assemble_ms = t.elapsed().as_secs_f64() * 1e3;

    let t = Instant::now();
    let cycle = levels.multigrid(MultigridOptions::default())?;
    let factor_ms = t.elapsed().as_secs_f64() * 1e3;

    let t = Instant::now();
    let (potential, pcg) = levels.solve(&cycle, MULTIGRID_REL_TOL)?;
    let solve_ms = t.elapsed().as_secs_f64() * 1e3;
    let stages = Stages {
        mesh_ms,
        assemble_ms,
        analyze_ms: factor_ms,
        factor_ms,
        solve_ms,
    };
    let mg = serde_json::json!({
        "levels": cycle.level_count(),
        "coarsest_triangles": hierarchy.levels()[0].triangles().len(),
        "iterations": pcg.iterations,
        "rel_residual": pcg.rel_residual,
    });
    report(&potential, points, &stages, Some(mg), json)
}

/// Prints φ (and ψ) at the points with the stage times, as JSON or text.
fn report(
    potential: &Potential,
    points: &[Point],
    stages: &Stages,
    multigrid: Option<serde_json::Value>,
    json: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let mesh = potential.mesh();
    let Stages {
        mesh_ms,
        assemble_ms,
        analyze_ms,
        factor_ms,
        solve_ms,
    } = *stages;
    let values = points
        .iter()
        .map(|&p| potential.phi_at(p, None))
        .collect::<Result<Vec<f64>, _>>()?;
    if json {
        let mut out = serde_json::json!({
            "triangles": mesh.triangles().len(),
            "vertices": mesh.vertices().len(),
            "values": values,
            "psi": points.iter().map(|&p| potential.psi_at(p, None)).collect::<Result<Vec<f64>, _>>()?,
            "timings_ms": {"mesh": mesh_ms, "assemble": assemble_ms, "analyze": analyze_ms, "factor": factor_ms, "solve": solve_ms, "total": mesh_ms + assemble_ms + factor_ms + solve_ms},
        });
        if let Some(mg) = multigrid {
            out["multigrid"] = mg;
        }
        println!("{out}");
    } else {
        println!(
            "{} triangles, {} vertices",
            mesh.triangles().len(),
            mesh.vertices().len()
        );
        println!(
            "mesh {mesh_ms:.1} ms, assemble {assemble_ms:.1} ms, factor {factor_ms:.1} ms (of which analysis {analyze_ms:.1} ms), solve {solve_ms:.1} ms"
        );
        if let Some(mg) = multigrid {
            println!("multigrid {mg}");
        }
        for (p, v) in points.iter().zip(&values) {
            println!("φ({}, {}) = {v:.12}", p.x, p.y);
        }
    }
    Ok(())
}

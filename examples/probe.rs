//! Solves a scene's potential and prints φ at given points, with the time of each stage —
//! for comparing against outside solvers (FreeFEM, scikit-fem) point by point.
//!
//! ```text
//! cargo run --release --example probe -- meshes/reference.json --max-area 0.0044 --at 1,1 --at 8,3 --json
//! ```
//!
//! `--sequential` orders, factors and solves on one thread ([`Parallelism::Sequential`]); by
//! default the ordering of large systems uses rayon's pool (the factorisation and solves stay
//! on one thread, see `Parallelism`). The mesher's two halves run on two threads either way.

use std::sync::Arc;
use std::time::Instant;

use harmonic_planner::fem::{Assembler, AssemblyOptions, Potential};
use harmonic_planner::mesh::Domain;
use harmonic_planner::solver::{Parallelism, SymbolicCholesky};
use harmonic_planner::{Point, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().filter(|a| !a.starts_with("--")).ok_or(
        "usage: probe SCENE.json [--max-area A] --at X,Y [--at X,Y ...] [--json] [--sequential]",
    )?;
    let mut scene = Scene::from_file(path)?;
    let mut points = Vec::new();
    let mut json = false;
    let mut parallelism = Parallelism::default();
    let mut i = 1;
    while i < args.len() {
        match args[i].as_str() {
            "--json" => json = true,
            "--sequential" => parallelism = Parallelism::Sequential,
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
    let values = points
        .iter()
        .map(|&p| potential.phi_at(p, None))
        .collect::<Result<Vec<f64>, _>>()?;
    if json {
        println!(
            "{}",
            serde_json::json!({
                "triangles": mesh.triangles().len(),
                "vertices": mesh.vertices().len(),
                "values": values,
                "psi": points.iter().map(|&p| potential.psi_at(p, None)).collect::<Result<Vec<f64>, _>>()?,
                "timings_ms": {"mesh": mesh_ms, "assemble": assemble_ms, "analyze": analyze_ms, "factor": factor_ms, "solve": solve_ms, "total": mesh_ms + assemble_ms + factor_ms + solve_ms},
            })
        );
    } else {
        println!(
            "{} triangles, {} vertices",
            mesh.triangles().len(),
            mesh.vertices().len()
        );
        println!(
            "mesh {mesh_ms:.1} ms, assemble {assemble_ms:.1} ms, factor {factor_ms:.1} ms (of which analysis {analyze_ms:.1} ms), solve {solve_ms:.1} ms"
        );
        for (p, v) in points.iter().zip(&values) {
            println!("φ({}, {}) = {v:.12}", p.x, p.y);
        }
    }
    Ok(())
}

//! `hplan plan --poly` (Triangle's .poly files) and `hplan plan --mesh-in` (meshes made by
//! Triangle or gmsh), end to end: paths reach the goal and stay in the exact free space;
//! files it cannot use get one line on stderr and a non-zero exit.

mod common;

use std::path::{Path, PathBuf};

use common::{hplan, run_json};
use harmonic_fixtures::mesh_file;
use harmonic_planner::mesh::geom::{
    polygon_contains, segment_polygon_distance, segment_segment_distance,
};
use harmonic_planner::mesh::io::poly::Pslg;
use harmonic_planner::{Point, inputs};
use serde_json::Value;

fn points(path: &Value) -> Vec<Point> {
    path["points"]
        .as_array()
        .expect("points")
        .iter()
        .map(|p| Point::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect()
}

/// Plans on `file` with `--poly` and checks every path against the file's exact polygons:
/// it reaches the goal, its vertices lie inside the outer boundary, and no segment of it
/// touches a hole or the outer boundary.
fn plans_clean(file: &Path, goal: &str, starts: &[&str]) {
    let free = Pslg::read(file)
        .and_then(|p| p.free_space())
        .expect("free space");
    let mut args = vec![
        "plan",
        "--json",
        "--poly",
        file.to_str().unwrap(),
        "--goal",
        goal,
    ];
    for s in starts {
        args.extend(["--start", s]);
    }
    let report = run_json(&args);
    let paths = report["paths"].as_array().expect("paths");
    assert_eq!(paths.len(), starts.len());
    assert_eq!(report["potential"]["interior_local_minima"], 0);
    let ring = &free.workspace;
    let n = ring.len();
    for path in paths {
        assert_eq!(path["status"], "reached_goal", "{}: {path}", file.display());
        let pts = points(path);
        assert!(pts.len() > 2);
        for w in pts.windows(2) {
            assert!(polygon_contains(ring, w[0]) && polygon_contains(ring, w[1]));
            let wall = (0..n)
                .map(|k| segment_segment_distance(w[0], w[1], ring[k], ring[(k + 1) % n]))
                .fold(f64::INFINITY, f64::min);
            assert!(
                wall > 0.0,
                "{}: {:?} touches the outer boundary",
                file.display(),
                w
            );
            for hole in &free.holes {
                assert!(
                    segment_polygon_distance(w[0], w[1], hole) > 0.0,
                    "{}: {:?} touches a hole",
                    file.display(),
                    w
                );
            }
        }
    }
}

#[test]
fn poly_files_with_holes_plan_clean_paths() {
    plans_clean(
        &mesh_file("triangle/two_hex.poly"),
        "3.8,1.8",
        &["0.2,0.2", "2,1.8", "0.3,1.5", "2.1,0.2"],
    );
    // Interior constraint segments and a vertex; a closed interior ring around a hole.
    plans_clean(
        &mesh_file("triangle/slits.poly"),
        "2.8,0.8",
        &["0.2,2.8", "0.8,0.4"],
    );
    plans_clean(
        &mesh_file("triangle/layers.poly"),
        "1.9,1.9",
        &["1.0,0.7", "0.1,0.1"],
    );
}

/// Runs `hplan ARGS`, which must fail with one line on stderr; returns it.
fn one_line_error(args: &[&str]) -> String {
    let out = hplan().args(args).output().expect("hplan runs");
    assert!(!out.status.success(), "hplan {args:?} succeeded");
    assert_eq!(out.status.code(), Some(1), "exit code of {args:?}");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("hplan: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hplan-inputs-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn an_unclosed_outer_boundary_gets_one_line() {
    let dir = temp_dir("open");
    // two_hex.poly with its first outer segment left out (the count lowered to match).
    let text = std::fs::read_to_string(mesh_file("triangle/two_hex.poly")).unwrap();
    let text = text.replace("36 1\n1 1 2 1\n", "35 1\n");
    assert!(!text.contains("\n1 1 2 1\n"));
    let open = dir.join("open.poly");
    std::fs::write(&open, text).unwrap();
    let err = one_line_error(&[
        "plan",
        "--poly",
        open.to_str().unwrap(),
        "--goal",
        "3.8,1.8",
        "--start",
        "0.2,0.2",
    ]);
    assert!(
        err.contains("open.poly: the outer boundary is not closed at vertex"),
        "{err}"
    );
    // A missing vertex file, a hole in no ring.
    let err = one_line_error(&[
        "plan",
        "--poly",
        dir.join("none.poly").to_str().unwrap(),
        "--goal",
        "1,1",
        "--start",
        "2,2",
    ]);
    assert!(err.contains("none.poly"), "{err}");
    let square = "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 2 2\n";
    std::fs::write(dir.join("hole.poly"), square).unwrap();
    let err = one_line_error(&[
        "plan",
        "--poly",
        dir.join("hole.poly").to_str().unwrap(),
        "--goal",
        "1,1",
        "--start",
        "3,3",
    ]);
    assert!(
        err.contains("line 12") && err.contains("no closed ring"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Checks the paths of a `--mesh-in` report against the mesh's exact boundary (its domain's
/// clearance leaves the goal edges out).
fn mesh_paths_clean(report: &Value, mesh: &Path) {
    let imported = inputs::read_mesh(mesh).expect("mesh");
    let domain = harmonic_planner::mesh::Domain::of_mesh(&imported.to_mesh(None).unwrap()).unwrap();
    let (lo, hi) = domain.bounding_box();
    for path in report["paths"].as_array().expect("paths") {
        assert_eq!(path["status"], "reached_goal", "{path}");
        let pts = points(path);
        for w in pts.windows(2) {
            for p in w {
                assert!(domain.contains_free(*p), "{p} outside the mesh");
                assert!((lo.x..=hi.x).contains(&p.x) && (lo.y..=hi.y).contains(&p.y));
            }
        }
        // Everything but the final approach to the goal edge keeps off the walls and pillar.
        let walls =
            harmonic_planner::mesh::Domain::of_mesh(&imported.to_mesh(Some(2)).unwrap()).unwrap();
        for w in pts.windows(2) {
            assert!(
                walls.segment_clearance(w[0], w[1]) > 0.0,
                "{:?} touches a wall",
                w
            );
        }
    }
}

#[test]
fn gmsh_mesh_with_the_goal_by_physical_group() {
    let ascii = mesh_file("gmsh/room.msh");
    let binary = mesh_file("gmsh/room_binary.msh");
    let starts = ["0.3,1", "1.5,0.2", "1.5,1.8", "2.5,1"];
    let run = |file: &Path, goal: &str| {
        let mut args = vec![
            "plan",
            "--json",
            "--mesh-in",
            file.to_str().unwrap(),
            "--goal-tag",
            goal,
        ];
        for s in &starts {
            args.extend(["--start", s]);
        }
        run_json(&args)
    };
    let by_name = run(&ascii, "exit");
    mesh_paths_clean(&by_name, &ascii);
    for path in by_name["paths"].as_array().unwrap() {
        // The exit is the side x = 4.
        let last = *points(path).last().unwrap();
        assert!((last.x - 4.0).abs() < 1e-9, "ends at {last}");
    }
    assert_eq!(by_name["mesh"]["triangles"], 853);
    // The same by number; from the binary file (its coordinates are the exact doubles the
    // ASCII file rounds to 16 digits) the same within rounding.
    assert_eq!(run(&ascii, "2")["paths"], by_name["paths"]);
    let from_binary = run(&binary, "exit");
    assert_eq!(from_binary["mesh"]["triangles"], 853);
    for (a, b) in from_binary["paths"]
        .as_array()
        .unwrap()
        .iter()
        .zip(by_name["paths"].as_array().unwrap())
    {
        assert_eq!(a["status"], b["status"]);
        let (la, lb) = (a["length"].as_f64().unwrap(), b["length"].as_f64().unwrap());
        assert!((la - lb).abs() <= 1e-9 * lb, "{la} vs {lb}");
    }
    // A tag the file does not have: one line listing those it has.
    let err = one_line_error(&[
        "plan",
        "--mesh-in",
        ascii.to_str().unwrap(),
        "--goal-tag",
        "door",
        "--start",
        "1,1",
    ]);
    assert!(
        err.contains("\"exit\"") && err.contains("\"walls\""),
        "{err}"
    );
    // The goal as a point of the mesh.
    let point = run_json(&[
        "plan",
        "--json",
        "--mesh-in",
        ascii.to_str().unwrap(),
        "--goal",
        "3.5,1.5",
        "--start",
        "0.3,1",
    ]);
    assert_eq!(point["paths"][0]["status"], "reached_goal");
}

#[test]
fn triangle_mesh_files_and_their_errors() {
    let dir = temp_dir("tri");
    // A mesh in Triangle's formats (as Triangle writes them): a square with its right side
    // marked 2, the rest 1.
    let n = 6;
    let mut node = format!("{} 2 0 1\n", (n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let m = if i == n {
                2
            } else if i == 0 || j == 0 || j == n {
                1
            } else {
                0
            };
            node += &format!(
                "{} {} {} {m}\n",
                j * (n + 1) + i + 1,
                i as f64 / n as f64,
                j as f64 / n as f64
            );
        }
    }
    let mut ele = format!("{} 3 0\n", 2 * n * n);
    let mut k = 1;
    for j in 0..n {
        for i in 0..n {
            let v = |a: usize, b: usize| (j + b) * (n + 1) + i + a + 1;
            ele += &format!(
                "{k} {} {} {}\n{} {} {} {}\n",
                v(0, 0),
                v(1, 0),
                v(1, 1),
                k + 1,
                v(0, 0),
                v(1, 1),
                v(0, 1)
            );
            k += 2;
        }
    }
    let base = dir.join("square.1");
    std::fs::write(dir.join("square.1.node"), &node).unwrap();
    std::fs::write(dir.join("square.1.ele"), &ele).unwrap();
    let report = run_json(&[
        "plan",
        "--json",
        "--mesh-in",
        base.to_str().unwrap(),
        "--goal-tag",
        "2",
        "--start",
        "0.1,0.5",
    ]);
    assert_eq!(report["paths"][0]["status"], "reached_goal");
    let last = *points(&report["paths"][0]).last().unwrap();
    assert!((last.x - 1.0).abs() < 1e-9, "ends at {last}");
    // A clockwise triangle is turned; a zero-area one is refused by its number.
    let flipped = ele.replacen("1 1 2 9\n", "1 1 9 2\n", 1);
    assert_ne!(flipped, ele);
    std::fs::write(dir.join("square.1.ele"), &flipped).unwrap();
    let again = run_json(&[
        "plan",
        "--json",
        "--mesh-in",
        base.to_str().unwrap(),
        "--goal-tag",
        "2",
        "--start",
        "0.1,0.5",
    ]);
    assert_eq!(again["paths"], report["paths"]);
    std::fs::write(
        dir.join("square.1.ele"),
        ele.replacen("1 1 2 9\n", "1 1 2 3\n", 1),
    )
    .unwrap();
    let err = one_line_error(&[
        "plan",
        "--mesh-in",
        base.to_str().unwrap(),
        "--goal-tag",
        "2",
        "--start",
        "0.1,0.5",
    ]);
    assert!(err.contains("triangle 1 has zero area"), "{err}");
    // A vertex no triangle uses.
    let extra = node.replacen(
        &format!("{} 2 0 1\n", (n + 1) * (n + 1)),
        &format!("{} 2 0 1\n", (n + 1) * (n + 1) + 1),
        1,
    ) + &format!("{} 5 5 0\n", (n + 1) * (n + 1) + 1);
    std::fs::write(dir.join("square.1.node"), extra).unwrap();
    std::fs::write(dir.join("square.1.ele"), &ele).unwrap();
    let err = one_line_error(&[
        "plan",
        "--mesh-in",
        base.to_str().unwrap(),
        "--goal-tag",
        "2",
        "--start",
        "0.1,0.5",
    ]);
    assert!(
        err.contains(&format!(
            "vertex {} is used by no triangle",
            (n + 1) * (n + 1) + 1
        )),
        "{err}"
    );
    // An edge in three triangles.
    std::fs::write(dir.join("square.1.node"), &node).unwrap();
    let three = ele.replacen(
        &format!("{} 3 0\n", 2 * n * n),
        &format!("{} 3 0\n", 2 * n * n + 1),
        1,
    ) + &format!("{} 1 2 10\n", 2 * n * n + 1);
    std::fs::write(dir.join("square.1.ele"), three).unwrap();
    let err = one_line_error(&[
        "plan",
        "--mesh-in",
        base.to_str().unwrap(),
        "--goal-tag",
        "2",
        "--start",
        "0.1,0.5",
    ]);
    assert!(err.contains("not a manifold"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Triangle's sample files, when `HARMONIC_TRIANGLE_DATA` names their directory (the
/// `triangle/data` directory of the PyPI `triangle` package).
#[test]
fn triangle_sample_files_with_holes() {
    let Some(dir) = std::env::var_os("HARMONIC_TRIANGLE_DATA")
        .map(PathBuf::from)
        .filter(|d| d.is_dir())
    else {
        eprintln!(
            "skipped: set HARMONIC_TRIANGLE_DATA to the triangle/data directory of the PyPI `triangle` package to plan on Triangle's sample files"
        );
        return;
    };
    plans_clean(
        &dir.join("A.poly"),
        "0.7,-0.76",
        &["0.25,-0.78", "0.47,-0.28"],
    );
    plans_clean(
        &dir.join("double_hex.poly"),
        "0.9,0.9",
        &["0.1,0.1", "0.4,0.6", "0.6,0.2"],
    );
    plans_clean(
        &dir.join("face.poly"),
        "0,80",
        &["0,-95", "-60,-20", "60,0"],
    );
    plans_clean(
        &dir.join("square_circle_hole.poly"),
        "3.5,-0.5",
        &["-3.5,-5.5", "0,-4.5"],
    );
    let err = one_line_error(&[
        "plan",
        "--poly",
        dir.join("box.poly").to_str().unwrap(),
        "--goal",
        "0.5,0.5",
        "--start",
        "2.5,2.5",
    ]);
    assert!(err.contains("the outer boundary is not closed"), "{err}");
}

//! Issue 20: every command of the README's tour runs as written, on inputs
//! made here (scenes from `spatch sphere`, meshes and clouds exported from
//! them, an elevation map from `render --depth`).

use crate::test_command::TestCommand;

/// The tour's commands: the lines of the first shell block after
/// "## A tour of the commands", without their comments.
fn tour_commands() -> Vec<Vec<String>> {
    let readme = include_str!("../../../README.md");
    let tour = readme
        .split("## A tour of the commands")
        .nth(1)
        .expect("README has a tour");
    let block = tour
        .split("```sh")
        .nth(1)
        .unwrap()
        .split("```")
        .next()
        .unwrap();
    block
        .lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| l.starts_with("spatch "))
        .map(|l| l.split_whitespace().skip(1).map(str::to_owned).collect())
        .collect()
}

/// A closed octahedron as OBJ, with sharp edges for the crease options.
const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

/// The tour's other inputs: an STL, a GLB, clouds in PLY, LAZ, PTS and 9-column text, a
/// pose file, and a scene far from the origin.
fn write_scan_inputs(t: &TestCommand) {
    let stl: String = OCTAHEDRON
        .lines()
        .filter_map(|l| l.strip_prefix("f "))
        .map(|f| {
            let corners: String = f
                .split(' ')
                .map(|i| {
                    let v = OCTAHEDRON
                        .lines()
                        .nth(i.parse::<usize>().unwrap() - 1)
                        .unwrap();
                    format!("vertex {}\n", &v[2..])
                })
                .collect();
            format!("facet normal 0 0 0\nouter loop\n{corners}endloop\nendfacet\n")
        })
        .collect();
    std::fs::write(
        t.path("part.stl"),
        format!("solid part\n{stl}endsolid part\n"),
    )
    .unwrap();
    t.run(&["export", "a.spatch", "--cells", "-o", "duck.glb"])
        .success();
    t.run(&["export", "a.spatch", "-o", "scans.ply"]).success();
    t.run(&["export", "a.spatch", "-o", "a.ply"]).success();
    std::fs::write(t.path("bun.conf"), "bmesh scan.ply 0 0 0 0 0 0 1\n").unwrap();
    crate::range_grid::write_sheet_scan(&t.path("bun000.ply"), 0.0);
    crate::scan_inputs::write_las(&t.path("b.laz"), &crate::scan_inputs::sheet(3.0));
    crate::scan_inputs::write_las(&t.path("site.las"), &crate::scan_inputs::sheet(3.0));
    let lines = |format: &dyn Fn(&[f64; 3]) -> String| -> String {
        crate::scan_inputs::sheet(5.0).iter().map(format).collect()
    };
    let pts = lines(&|p| format!("{} {} {} -200 10 20 30\n", p[0], p[1], p[2]));
    std::fs::write(t.path("c.pts"), format!("3600\n{pts}")).unwrap();
    let text = lines(&|p| format!("{} {} {} 0 0 1 200 100 50\n", p[0], p[1], p[2]));
    std::fs::write(t.path("scan.txt"), text).unwrap();
    let far = "5e5,4e6,0";
    let utm = [
        "merge",
        "a.spatch",
        "b.spatch",
        "--translate",
        far,
        "--translate",
        far,
    ];
    t.run(&[&utm[..], &["-o", "utm.spatch"]].concat()).success();
}

#[test]
fn every_readme_tour_command_runs_as_written() {
    let t = TestCommand::new();
    for scene in [
        "bunny.spatch",
        "sphere.spatch",
        "a.spatch",
        "b.spatch",
        "scan.spatch",
        "cylinder.spatch",
    ] {
        t.small_sphere(scene);
    }
    t.run(&["export", "a.spatch", "--cells", "-o", "bunny.ply"])
        .success();
    t.run(&["export", "a.spatch", "-o", "scan.ply"]).success();
    t.run(&["render", "a.spatch", "-o", "x.png", "--depth", "dem.png"])
        .success();
    for mesh in ["fuze.obj", "part.obj"] {
        std::fs::write(t.path(mesh), OCTAHEDRON).unwrap();
    }
    write_scan_inputs(&t);
    let commands = tour_commands();
    assert!(commands.len() >= 15, "{commands:?}");
    for args in commands {
        // The sweep converts the mesh 24 times and renders it 36 times: minutes in a test
        // build. `eval::a_tiny_sweep_writes_its_table_json_and_plot_with_a_correct_front`
        // runs the same command on smaller lists.
        if args.iter().any(|a| a == "--sweep") {
            continue;
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        t.run(&args).success();
    }
}

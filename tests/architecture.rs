//! The layer rule of docs/architecture.md, checked on the source: each top-level module uses
//! (`crate::...` outside comments) only modules of the layers below its own, or the peers listed
//! before it in its own layer; so no two modules use each other.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Lowest first; within a layer, a module may use the peers listed before it.
const LAYERS: &[&[&str]] = &[
    &["error", "simd", "geometry", "variant"],
    &["parse"],
    &["accel", "camera"],
    &["scene"],
    &["shade", "trace", "sample"],
    &["render", "inspect", "image_io"],
    &["job", "check", "preview"],
    &["cli"],
];

/// (layer, place in the layer) of a top-level module.
fn rank(module: &str) -> Option<(usize, usize)> {
    LAYERS.iter().enumerate().find_map(|(layer, peers)| {
        peers
            .iter()
            .position(|&peer| peer == module)
            .map(|place| (layer, place))
    })
}

/// Every top-level module of `src/` and the modules its code uses.
fn module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut pending = vec![src.clone()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
                continue;
            }
            let relative = path.strip_prefix(&src).unwrap();
            let first = relative.components().next().unwrap().as_os_str();
            let module = first.to_string_lossy().trim_end_matches(".rs").to_string();
            if module == "lib" || module == "main" {
                continue;
            }
            let used = graph.entry(module.clone()).or_default();
            let text = std::fs::read_to_string(&path).unwrap();
            for line in text.lines() {
                let code = line.split("//").next().unwrap();
                for (at, _) in code.match_indices("crate::") {
                    let name: String = code[at + "crate::".len()..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if !name.is_empty() && name != module {
                        used.insert(name);
                    }
                }
            }
        }
    }
    graph
}

#[test]
fn imports_point_down_the_pipeline() {
    let graph = module_graph();
    let mut broken = Vec::new();
    for (module, used) in &graph {
        let Some(own) = rank(module) else {
            broken.push(format!("{module} is in no layer of LAYERS"));
            continue;
        };
        for target in used {
            match rank(target) {
                Some(theirs) if theirs < own => {}
                Some(_) => broken.push(format!("{module} uses {target}, above or beside it")),
                None => broken.push(format!("{module} uses {target}, which is in no layer")),
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
    // The layers name no module that is gone.
    for module in LAYERS.iter().flat_map(|peers| peers.iter()) {
        assert!(
            graph.contains_key(*module),
            "{module} is listed but not in src/"
        );
    }
}

#[test]
fn the_graph_reads_uses_of_other_modules() {
    // The reader must see the uses it judges: the pixel loop uses the tracer, the tracer the
    // scene, the grader the render jobs (it renders the suite's lines under faults), and the
    // program the grader.
    let graph = module_graph();
    assert!(graph["render"].contains("trace"));
    assert!(graph["trace"].contains("scene"));
    assert!(graph["check"].contains("job"));
    assert!(graph["cli"].contains("check"));
}

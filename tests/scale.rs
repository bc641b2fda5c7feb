//! Rays right at any scale: the same scene scaled as a whole (its objects by a Transform, the
//! camera's centre with them) must give the same picture, shadows and mirrors included. With a
//! fixed offset for shadow rays (the course's 1e-4) the bunny at a thousandth lost its shadows
//! (1.8 % of pixels off) and at ten thousand times speckled (6.1 %), Nefertiti 3.0 % and 7.9 %.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn meshes() -> Option<PathBuf> {
    common::data_dir(
        "the scale tests on the big meshes",
        "RAYCAST_MESHES_DIR",
        "../shared/meshes",
        "stanford-bunny.obj",
    )
}

/// A scene of one mesh under `Scale s s s`, seen by a perspective camera whose centre is
/// scaled with it, lit by one directional light; with `mirror`, a mirror floor under it.
struct Setup<'a> {
    mesh: &'a Path,
    center: [f64; 3],
    direction: &'a str,
    up: &'a str,
    light: &'a str,
    mirror_floor: Option<f64>,
}

impl Setup<'_> {
    fn text(&self, s: f64) -> String {
        let [x, y, z] = self.center.map(|c| c * s);
        let (materials, objects) = match self.mirror_floor {
            None => (
                "Materials { numMaterials 1 Material { diffuseColor 0.9 0.9 0.9 } }".to_string(),
                format!(
                    "Group {{ numObjects 1 MaterialIndex 0 TriangleMesh {{ obj_file {} }} }}",
                    self.mesh.display()
                ),
            ),
            Some(floor) => (
                "Materials { numMaterials 2 Material { diffuseColor 0.9 0.9 0.9 }
                     Material { diffuseColor 0.2 0.2 0.3 reflectiveColor 0.6 0.6 0.6 } }"
                    .to_string(),
                format!(
                    "Group {{ numObjects 2 MaterialIndex 0 TriangleMesh {{ obj_file {} }}
                         MaterialIndex 1 Plane {{ normal 0 1 0 offset {floor} }} }}",
                    self.mesh.display()
                ),
            ),
        };
        format!(
            "PerspectiveCamera {{ center {x} {y} {z} direction {} up {} angle 30 }}
             Lights {{ numLights 1 DirectionalLight {{ direction {} color 0.9 0.9 0.85 }} }}
             Background {{ color 0.2 0.2 0.2 ambientLight 0.1 0.1 0.1 }}
             {materials}
             Group {{ numObjects 1 Transform {{ Scale {s} {s} {s} {objects} }} }}",
            self.direction, self.up, self.light
        )
    }
}

/// The share of pixels off by more than 2 levels between two pictures of the same size.
fn off(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    let bad = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    bad as f64 / f64::from(a.width() * a.height())
}

fn render(dir: &Path, name: &str, text: &str, extra: &[&str]) -> image::RgbImage {
    let scene = dir.join(format!("{name}.txt"));
    let out = dir.join(format!("{name}.png"));
    std::fs::write(&scene, text).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .arg("-input")
        .arg(&scene)
        .args(["-size", "96", "96", "-output"])
        .arg(&out)
        .args(extra)
        .status()
        .unwrap();
    assert!(status.success());
    image::open(&out).unwrap().to_rgb8()
}

fn scale_invariant(name: &str, setup: &Setup, extra: &[&str]) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let unscaled = render(dir.path(), "k0", &setup.text(1.0), extra);
    let mut wrong = Vec::new();
    for k in [-3, -2, -1, 1, 2, 3, 4] {
        let scaled = render(
            dir.path(),
            &format!("k{k}"),
            &setup.text(10f64.powi(k)),
            extra,
        );
        let off = off(&scaled, &unscaled);
        println!("{name} at 10^{k}: {:.3}% of pixels off", 100.0 * off);
        if off > 0.001 {
            wrong.push(format!(
                "{name} at 10^{k}: {:.3}% of pixels off",
                100.0 * off
            ));
        }
    }
    wrong
}

#[test]
fn shadows_and_mirrors_are_the_same_at_every_scale() {
    let Some(meshes) = meshes() else {
        return;
    };
    let bunny = meshes.join("stanford-bunny.obj");
    let nefertiti = meshes.join("nefertiti.obj");
    let bunny_setup = Setup {
        mesh: &bunny,
        center: [-0.367659, 0.288879, 0.266634],
        direction: "0.717496 -0.394623 -0.573997",
        up: "0 1 0",
        light: "0.3 -0.8 -0.6",
        mirror_floor: None,
    };
    let nefertiti_setup = Setup {
        mesh: &nefertiti,
        center: [673.413, -1093.73, 377.99],
        direction: "-0.492781 0.821302 -0.287456",
        up: "0 0 1",
        light: "-0.2 0.7 -0.6",
        mirror_floor: None,
    };
    // The bunny stands on y = 0.033: a mirror just under it.
    let mirrored = Setup {
        mirror_floor: Some(0.0325),
        ..Setup {
            mesh: &bunny,
            ..bunny_setup
        }
    };
    let mut wrong = scale_invariant("bunny", &bunny_setup, &["-shadows"]);
    wrong.extend(scale_invariant(
        "nefertiti",
        &nefertiti_setup,
        &["-shadows"],
    ));
    wrong.extend(scale_invariant(
        "bunny over a mirror",
        &mirrored,
        &["-shadows", "-bounces", "2"],
    ));
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

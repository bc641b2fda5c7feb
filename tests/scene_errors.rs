//! What raycast says about scene and mesh files it cannot render: every message exactly, with
//! the line and column it points at. The library is called directly (`parse_scene`,
//! `Scene::from_description`, `Scene::load`); tests/cli.rs checks how the program reports them.

use std::path::Path;

use raycast::Scene;
use raycast::parse::parse_scene;

const CAMERA: &str = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }";
const MATERIAL: &str = "Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }";

/// The message `parse_scene` gives for `text`, read as the file `s.txt`.
fn parse_error(text: &str) -> String {
    match parse_scene(Path::new("s.txt"), text) {
        Ok(_) => panic!("the scene parsed, but an error was expected:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// A scene of a camera and one material (lines 1 and 2) whose root Group, on line 3, is `group`.
fn with_group(group: &str) -> String {
    format!("{CAMERA}\n{MATERIAL}\n{group}\n")
}

/// The message for a scene that parses but cannot be built into a render-ready scene.
fn build_error(text: &str) -> String {
    let description = parse_scene(Path::new("s.txt"), text).expect("the scene should parse");
    match Scene::from_description(&description) {
        Ok(_) => panic!("the scene was built, but an error was expected:\n{text}"),
        Err(e) => e.to_string(),
    }
}

// ---------------------------------------------------------------------------------------------
// Words that do not belong where they stand

#[test]
fn an_unknown_top_level_word() {
    assert_eq!(
        parse_error(&format!("{CAMERA}\nFoo {{ }}\n")),
        "s.txt:2:1: expected a scene block (OrthographicCamera, PerspectiveCamera, Background, \
         Lights, Materials or Group), found 'Foo'"
    );
}

#[test]
fn a_misspelt_field() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { centre 0 0 0 radius 1 } }"
        )),
        "s.txt:3:47: expected 'center', found 'centre'"
    );
    assert_eq!(
        parse_error(&format!("{CAMERA}\nBackground {{ colour 1 1 1 }}\n")),
        "s.txt:2:14: expected color, ambientLight or '}', found 'colour'"
    );
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 5 }"),
        "s.txt:1:62: expected 'size', found 'angle'"
    );
}

#[test]
fn a_word_where_a_number_belongs() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 x 0 radius 1 } }"
        )),
        "s.txt:3:56: expected a number, found 'x'"
    );
    // A brace where the third coordinate should be: the vector is cut short.
    assert_eq!(
        parse_error(&format!("{CAMERA}\nBackground {{ color 1 1 }}\n")),
        "s.txt:2:24: expected a number, found '}'"
    );
    assert_eq!(
        parse_error(&with_group("Group { numObjects -1 }")),
        "s.txt:3:20: expected a whole number from 0 to 4294967295 for numObjects, found '-1'"
    );
    assert_eq!(
        parse_error(&with_group("Group { numObjects 1 MaterialIndex 0.5 }")),
        "s.txt:3:36: expected a whole number from 0 to 4294967295 for MaterialIndex, found '0.5'"
    );
}

#[test]
fn numbers_beyond_1e9_and_non_numbers_are_refused() {
    for word in [
        "1e39",
        "-1e39",
        "3e38",
        "1e20",
        "1e15",
        "1.000001e9",
        "-2e9",
        "nan",
        "NaN",
        "inf",
        "-inf",
        "infinity",
    ] {
        let scene = with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Sphere {{ center 0 {word} 0 radius 1 }} }}"
        ));
        assert_eq!(
            parse_error(&scene),
            format!("s.txt:3:56: expected a number between -1e9 and 1e9, found '{word}'")
        );
    }
    // The bound itself is fine, and so are numbers too small for single precision: they are 0.
    for word in ["1e9", "-1e9", "1e-45", "-1e-300"] {
        let scene = with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Sphere {{ center 0 {word} 0 radius 1 }} }}"
        ));
        parse_scene(Path::new("s.txt"), &scene).unwrap();
    }
}

#[test]
fn every_kind_of_number_is_bounded() {
    // A radius that overflows single precision when squared: the sphere was never hit.
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 3e38 } }"
        )),
        "s.txt:3:67: expected a number between -1e9 and 1e9, found '3e38'"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Plane { normal 0 1 0 offset -1e20 } }"
        )),
        "s.txt:3:66: expected a number between -1e9 and 1e9, found '-1e20'"
    );
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 1e15 }"),
        "s.txt:1:67: expected a number between -1e9 and 1e9, found '1e15'"
    );
    // Before the bound, a direction this long squared to infinity and was called zero-length.
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 3e38 0 0 up 0 1 0 size 5 }"),
        "s.txt:1:46: expected a number between -1e9 and 1e9, found '3e38'"
    );
    assert_eq!(
        parse_error(&format!("{CAMERA}\nBackground {{ color 1e10 0 0 }}\n")),
        "s.txt:2:20: expected a number between -1e9 and 1e9, found '1e10'"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { XRotate 1e300 Sphere { center 0 0 0 radius 1 } } }"
        )),
        "s.txt:3:58: expected a number between -1e9 and 1e9, found '1e300'"
    );
    // Nested UniformScale 1e20 rendered nothing: the first one is refused now.
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { UniformScale 1e20 \
             Transform { UniformScale 1e20 Sphere { center 0 0 0 radius 1 } } } }"
        )),
        "s.txt:3:63: expected a number between -1e9 and 1e9, found '1e20'"
    );
}
#[test]
fn end_of_file_inside_a_block() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0"
        )),
        "s.txt:4:1: expected 'radius', found end of file"
    );
    // Without a final newline the end is just past the last character.
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0"),
        "s.txt:1:32: expected a number, found end of file"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0\n  Transform { Translate 1 0 0\n    Sphere { center 0 0 0 radius 1 }"
        )),
        "s.txt:6:1: expected '}', found end of file"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 }"
        )),
        "s.txt:4:1: expected '}' (the Group's numObjects is 1), found end of file"
    );
}

#[test]
fn a_file_cut_short_before_its_group() {
    // It would render as background alone, as a tracer that misses everything does.
    assert_eq!(
        parse_error(&format!("{CAMERA}\n{MATERIAL}\n")),
        "s.txt:3:1: expected the scene's Group (its objects; every scene has one, after the \
         camera), found end of file"
    );
    assert_eq!(
        parse_error(&format!("{CAMERA}\nBackground {{ color 0 0 0 }}")),
        "s.txt:2:27: expected the scene's Group (its objects; every scene has one, after the \
         camera), found end of file"
    );
}

#[test]
fn a_brace_glued_to_a_word_gets_a_hint() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere{ center 0 0 0 radius 1 } }"
        )),
        "s.txt:3:38: expected an object (Group, Transform, Sphere, Plane, Triangle or \
         TriangleMesh), found 'Sphere{' (braces must stand apart, with spaces around them)"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1} }"
        )),
        "s.txt:3:67: expected a number, found '1}' (braces must stand apart, with spaces around them)"
    );
    assert_eq!(
        parse_error("Group{ numObjects 0 }"),
        "s.txt:1:1: expected a scene block (OrthographicCamera, PerspectiveCamera, Background, \
         Lights, Materials or Group), found 'Group{' (braces must stand apart, with spaces around them)"
    );
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { Translate 0 0 0 Sphere { center 0 0 0 radius 1 } }}"
        )),
        "s.txt:3:99: expected '}', found '}}' (braces must stand apart, with spaces around them)"
    );
}

// ---------------------------------------------------------------------------------------------
// Counted lists

#[test]
fn fewer_objects_than_num_objects() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 2 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }"
        )),
        "s.txt:3:71: expected 1 more object (the Group's numObjects is 2), found '}'"
    );
    assert_eq!(
        parse_error(&with_group("Group { numObjects 3 MaterialIndex 0 }")),
        "s.txt:3:38: expected 3 more objects (the Group's numObjects is 3), found '}'"
    );
}

#[test]
fn more_objects_than_num_objects() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } Sphere { center 0 0 0 radius 1 } }"
        )),
        "s.txt:3:71: expected '}' (the Group's numObjects is 1), found 'Sphere'"
    );
}

#[test]
fn material_and_light_counts_that_do_not_match() {
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nMaterials {{ numMaterials 2 Material {{ diffuseColor 1 0 0 }} }}\n"
        )),
        "s.txt:2:60: expected 1 more material (numMaterials is 2), found '}'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nMaterials {{ numMaterials 1 Material {{ diffuseColor 1 0 0 }} Material {{ }} }}\n"
        )),
        "s.txt:2:60: expected '}' (numMaterials is 1), found 'Material'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nLights {{ numLights 2 DirectionalLight {{ direction 0 0 1 color 1 1 1 }} }}\n"
        )),
        "s.txt:2:71: expected 1 more light (numLights is 2), found '}'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nLights {{ numLights 0 DirectionalLight {{ direction 0 0 1 color 1 1 1 }} }}\n"
        )),
        "s.txt:2:22: expected '}' (numLights is 0), found 'DirectionalLight'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nLights {{ numLights 1 SpotLight {{ direction 0 0 1 color 1 1 1 }} }}\n"
        )),
        "s.txt:2:22: expected DirectionalLight or PointLight, found 'SpotLight'"
    );
}

// ---------------------------------------------------------------------------------------------
// Materials

#[test]
fn material_index_out_of_range() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 1 Sphere { center 0 0 0 radius 1 } }"
        )),
        "s.txt:3:36: expected material index 0 (the scene has 1 material), found '1'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nMaterials {{ numMaterials 3 Material {{ }} Material {{ }} Material {{ }} }}\n\
             Group {{ numObjects 1 MaterialIndex 3 Sphere {{ center 0 0 0 radius 1 }} }}\n"
        )),
        "s.txt:3:36: expected a material index from 0 to 2 (the scene has 3 materials), found '3'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nGroup {{ numObjects 1 MaterialIndex 0 Sphere {{ center 0 0 0 radius 1 }} }}\n"
        )),
        "s.txt:2:36: expected no MaterialIndex (the scene has no materials), found '0'"
    );
}

#[test]
fn material_index_is_checked_against_materials_that_come_after_the_group() {
    let group = "Group { numObjects 1 MaterialIndex 1 Sphere { center 0 0 0 radius 1 } }";
    assert_eq!(
        parse_error(&format!("{CAMERA}\n{group}\n{MATERIAL}\n")),
        "s.txt:2:36: expected material index 0 (the scene has 1 material), found '1'"
    );
    // ...and an index that the later Materials block does provide is fine.
    let two = "Materials { numMaterials 2 Material { } Material { } }";
    let description =
        parse_scene(Path::new("s.txt"), &format!("{CAMERA}\n{group}\n{two}\n")).unwrap();
    assert_eq!(description.objects[0].material, 1);
}

#[test]
fn an_object_before_any_material_index() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 Sphere { center 0 0 0 radius 1 } }"
        )),
        "s.txt:3:22: expected MaterialIndex before the first object, found 'Sphere'"
    );
    // MaterialIndex may not stand directly inside a Transform.
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 Transform { MaterialIndex 0 Sphere { center 0 0 0 radius 1 } } }"
        )),
        "s.txt:3:34: expected an object (Group, Transform, Sphere, Plane, Triangle or \
         TriangleMesh), found 'MaterialIndex'"
    );
}

// ---------------------------------------------------------------------------------------------
// Assignment 4's materials and lights

/// The scene's materials and lights, from `Materials { ... }` and `Lights { ... }` blocks.
fn materials_and_lights(
    blocks: &str,
) -> (
    Vec<raycast::parse::description::MaterialSpec>,
    Vec<raycast::parse::description::LightSpec>,
) {
    let description = parse_scene(
        Path::new("s.txt"),
        &format!("{CAMERA}\n{blocks}\nGroup {{ numObjects 0 }}\n"),
    )
    .unwrap();
    (description.materials, description.lights)
}

#[test]
fn phong_fields_are_optional_and_in_any_order() {
    use glam::Vec3;
    use raycast::parse::description::{MaterialSpec, PhongSpec};
    let (materials, _) = materials_and_lights(
        "Materials { numMaterials 3
            PhongMaterial { }
            Material { indexOfRefraction 1.5 transparentColor 0.1 0.2 0.3 exponent 20
                reflectiveColor 0.4 0.5 0.6 specularColor 0.7 0.8 0.9 diffuseColor 0 0.5 1 }
            PhongMaterial { exponent 0 exponent 3 } }",
    );
    assert_eq!(materials[0], MaterialSpec::Phong(PhongSpec::default()));
    assert_eq!(
        materials[0],
        MaterialSpec::Phong(PhongSpec {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            exponent: 1.0,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            index_of_refraction: 1.0,
        })
    );
    assert_eq!(
        materials[1],
        MaterialSpec::Phong(PhongSpec {
            diffuse: Vec3::new(0.0, 0.5, 1.0),
            specular: Vec3::new(0.7, 0.8, 0.9),
            exponent: 20.0,
            reflective: Vec3::new(0.4, 0.5, 0.6),
            transparent: Vec3::new(0.1, 0.2, 0.3),
            index_of_refraction: 1.5,
        })
    );
    // As the course's parser: a field given twice keeps its last value.
    assert!(matches!(
        materials[2],
        MaterialSpec::Phong(PhongSpec { exponent: 3.0, .. })
    ));
}

#[test]
fn point_lights_with_and_without_attenuation() {
    use glam::Vec3;
    use raycast::parse::description::LightSpec;
    let (_, lights) = materials_and_lights(
        "Lights { numLights 3
            PointLight { position 1 2 3 color 0.5 0.5 0.5 }
            DirectionalLight { direction 0 -2 0 color 1 1 1 }
            PointLight { position 0 0 0 color 1 0 0 attenuation 0 0.5 0.25 } }",
    );
    assert_eq!(
        lights,
        [
            LightSpec::Point {
                position: Vec3::new(1.0, 2.0, 3.0),
                colour: Vec3::splat(0.5),
                attenuation: [1.0, 0.0, 0.0],
            },
            LightSpec::Directional {
                direction: Vec3::new(0.0, -1.0, 0.0),
                colour: Vec3::ONE,
            },
            LightSpec::Point {
                position: Vec3::ZERO,
                colour: Vec3::new(1.0, 0.0, 0.0),
                attenuation: [0.0, 0.5, 0.25],
            },
        ]
    );
}

#[test]
fn material_values_that_make_no_sense() {
    let material = |fields: &str| {
        parse_error(&format!(
            "{CAMERA}\nMaterials {{ numMaterials 1 Material {{ {fields} }} }}\n"
        ))
    };
    assert_eq!(
        material("exponent -2"),
        "s.txt:2:48: expected a specular exponent of 0 or more, found '-2'"
    );
    assert_eq!(
        material("indexOfRefraction 0"),
        "s.txt:2:57: expected an index of refraction above 0, found '0'"
    );
    assert_eq!(
        material("indexOfRefraction -1.5"),
        "s.txt:2:57: expected an index of refraction above 0, found '-1.5'"
    );
    assert_eq!(
        material("indexOfRefraction 1e-50"),
        "s.txt:2:57: expected an index of refraction above 0, found '1e-50' (so small that \
         single precision rounds it to zero)"
    );
    assert_eq!(
        material("shininess 4"),
        "s.txt:2:39: expected diffuseColor, specularColor, exponent, reflectiveColor, \
         transparentColor, indexOfRefraction or '}', found 'shininess'"
    );
    assert_eq!(
        material("reflectiveColor 1 1"),
        "s.txt:2:59: expected a number, found '}'"
    );
}

#[test]
fn point_light_values_that_make_no_sense() {
    let light = |body: &str| {
        parse_error(&format!(
            "{CAMERA}\nLights {{ numLights 1 PointLight {{ {body} }} }}\n"
        ))
    };
    assert_eq!(
        light("position 0 0 0 color 1 1 1 attenuation 0 0 0"),
        "s.txt:2:62: expected attenuation with at least one term above 0 (1 0 0: no \
         fall-off), found '0 0 0', which would make the light infinitely bright"
    );
    assert_eq!(
        light("position 0 0 0 color 1 1 1 attenuation 1 -0.5 0"),
        "s.txt:2:76: expected an attenuation term of 0 or more, found '-0.5'"
    );
    // The fields come in the course's fixed order.
    assert_eq!(
        light("color 1 1 1 position 0 0 0"),
        "s.txt:2:35: expected 'position', found 'color'"
    );
    assert_eq!(
        light("position 0 0 0 color 1 1 1 falloff 2"),
        "s.txt:2:62: expected attenuation or '}', found 'falloff'"
    );
    assert_eq!(
        light("position 0 0 0 color 1 1 1 attenuation 1 0 0 attenuation 1 0 0"),
        "s.txt:2:80: expected '}', found 'attenuation'"
    );
}

// ---------------------------------------------------------------------------------------------
// Values a shape or camera cannot have

#[test]
fn sphere_radius_must_be_positive() {
    for (radius, found) in [
        ("-1", "'-1'"),
        ("0", "'0'"),
        ("-0", "'-0'"),
        (
            "1e-46",
            "'1e-46' (so small that single precision rounds it to zero)",
        ),
    ] {
        let scene = with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Sphere {{ center 0 0 0 radius {radius} }} }}"
        ));
        assert_eq!(
            parse_error(&scene),
            format!("s.txt:3:67: expected a positive radius, found {found}")
        );
    }
}

#[test]
fn plane_normal_must_have_length() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Plane { normal 0 0 0 offset 1 } }"
        )),
        "s.txt:3:53: expected a plane normal of non-zero length, found '0 0 0'"
    );
}

#[test]
fn camera_direction_must_have_length() {
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 0 up 0 1 0 size 5 }"),
        "s.txt:1:46: expected a direction of non-zero length, found '0 0 0'"
    );
    // Tiny values are shown with an exponent, not as thirty zeros.
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1e-30 up 0 1 0 size 5 }"),
        "s.txt:1:46: expected a direction of non-zero length, found '0 0 -1e-30'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nLights {{ numLights 1 DirectionalLight {{ direction 0 0 0 color 1 1 1 }} }}\n"
        )),
        "s.txt:2:51: expected a direction of non-zero length, found '0 0 0'"
    );
}

#[test]
fn camera_up_must_not_be_parallel_to_direction() {
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 1 0 up 0 2 0 size 5 }"),
        "s.txt:1:55: expected an up vector that is not parallel to the direction, found '0 2 0'"
    );
    assert_eq!(
        parse_error("PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 0 3.5 angle 30 }"),
        "s.txt:1:55: expected an up vector that is not parallel to the direction, found '0 0 3.5'"
    );
    assert_eq!(
        parse_error("PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 0 0 angle 30 }"),
        "s.txt:1:55: expected an up vector that is not parallel to the direction, found '0 0 0'"
    );
}

#[test]
fn perspective_angle_must_be_between_0_and_180() {
    // 179.9999999 is below 180, but its f32 radians round up to π: the picture would flip.
    for angle in ["0", "180", "-30", "180.0", "360", "179.9999999"] {
        let scene = format!(
            "PerspectiveCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 angle {angle} }}"
        );
        assert_eq!(
            parse_error(&scene),
            format!("s.txt:1:67: expected an angle between 0 and 180 degrees, found '{angle}'")
        );
    }
}

#[test]
fn orthographic_size_must_be_positive() {
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 0 }"),
        "s.txt:1:67: expected a positive size, found '0'"
    );
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size -5 }"),
        "s.txt:1:67: expected a positive size, found '-5'"
    );
    assert_eq!(
        parse_error("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 1e-50 }"),
        "s.txt:1:67: expected a positive size, found '1e-50' (so small that single precision rounds it to zero)"
    );
}

#[test]
fn singular_transforms_are_refused() {
    let sphere = "Sphere { center 0 0 0 radius 1 }";
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ Scale 1 0 1 {sphere} }} }}"
        ))),
        "s.txt:3:56: expected an invertible transformation, found one that flattens space (its scales multiply to zero)"
    );
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ UniformScale 0 {sphere} }} }}"
        ))),
        "s.txt:3:63: expected an invertible transformation, found one that flattens space (its scales multiply to zero)"
    );
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ Matrix {{ 1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1 }} {sphere} }} }}"
        ))),
        "s.txt:3:59: expected an invertible transformation, found one that flattens space (its scales multiply to zero)"
    );
    // Each scale alone is not zero; multiplied (in double precision), they are: the error points
    // at the Transform whose matrix is singular.
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0\n\
             Transform {{ UniformScale 1e-200 UniformScale 1e-200 {sphere} }} }}"
        ))),
        "s.txt:4:1: expected an invertible transformation, found one that flattens space (its scales multiply to zero)"
    );
}

#[test]
fn transforms_that_scale_or_move_beyond_1e9_are_refused() {
    let sphere = "Sphere { center 0 0 0 radius 1 }";
    // Each scale is within bounds; nested, they multiply past them. The error points at the
    // Transform whose combined matrix is out of bounds.
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0\n\
             Transform {{ UniformScale 1e5\n\
             Transform {{ UniformScale 1e5 {sphere} }} }} }}"
        ))),
        "s.txt:5:1: expected a transformation whose matrix, with the Transforms around it, has \
         entries between -1e9 and 1e9, found an entry of 1e10"
    );
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0\n\
             Transform {{ Translate 6e8 0 0 Translate 6e8 0 0 {sphere} }} }}"
        ))),
        "s.txt:4:1: expected a transformation whose matrix, with the Transforms around it, has \
         entries between -1e9 and 1e9, found an entry of 1.2e9"
    );
    // Shrinking too far: the inverse, which carries rays into the object, is out of bounds.
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0\n\
             Transform {{ UniformScale 1e-5\n\
             Transform {{ Scale 1 1e-5 1 {sphere} }} }} }}"
        ))),
        "s.txt:5:1: expected a transformation whose inverse, with the Transforms around it, has \
         entries between -1e9 and 1e9, found an entry of 1e10 (it shrinks space too much)"
    );
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ Matrix {{ 1e-10 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 }} {sphere} }} }}"
        ))),
        "s.txt:3:38: expected a transformation whose inverse, with the Transforms around it, has \
         entries between -1e9 and 1e9, found an entry of 1e10 (it shrinks space too much)"
    );
    // At the bounds, both ways, it is fine.
    for ops in [
        "UniformScale 1e9",
        "UniformScale 1e-9",
        "Translate -1e9 0 0",
    ] {
        let scene = with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ {ops} {sphere} }} }}"
        ));
        parse_scene(Path::new("s.txt"), &scene).unwrap();
    }
}

#[test]
fn a_matrix_must_be_affine() {
    let sphere = "Sphere { center 0 0 0 radius 1 }";
    // The last row was dropped without a word; it is refused at its first number.
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{ Matrix {{ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1 }} {sphere} }} }}"
        ))),
        "s.txt:3:83: expected a last row of '0 0 0 1' (raycast does only affine transformations), \
         found '0 0 1 1'"
    );
    assert_eq!(
        parse_error(&with_group(&format!(
            "Group {{ numObjects 1 MaterialIndex 0 Transform {{\n\
             Matrix {{\n 2 0 0 0\n 0 2 0 0\n 0 0 2 0\n 0 0 0 2 }}\n{sphere} }} }}"
        ))),
        "s.txt:8:2: expected a last row of '0 0 0 1' (raycast does only affine transformations), \
         found '0 0 0 2'"
    );
    // Written otherwise, the same numbers are fine.
    let scene = with_group(&format!(
        "Group {{ numObjects 1 MaterialIndex 0 Transform {{ Matrix {{ 1 0 0 0 0 1 0 0 0 0 1 0 -0 0.0 0 1.0 }} {sphere} }} }}"
    ));
    parse_scene(Path::new("s.txt"), &scene).unwrap();
}

#[test]
fn rotation_about_no_axis_is_refused() {
    assert_eq!(
        parse_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { Rotate { 0 0 0 45 } Sphere { center 0 0 0 radius 1 } } }"
        )),
        "s.txt:3:59: expected a rotation axis of non-zero length, found '0 0 0'"
    );
}

#[test]
fn a_scene_without_a_camera() {
    assert_eq!(
        parse_error(&format!(
            "{MATERIAL}\nGroup {{ numObjects 1 MaterialIndex 0 Sphere {{ center 0 0 0 radius 1 }} }}\n"
        )),
        "s.txt:3:1: expected a camera (OrthographicCamera or PerspectiveCamera), found end of file"
    );
    assert_eq!(
        parse_error(""),
        "s.txt:1:1: expected a camera (OrthographicCamera or PerspectiveCamera), found end of file"
    );
    assert_eq!(
        parse_error("\n\n   "),
        "s.txt:3:4: expected a camera (OrthographicCamera or PerspectiveCamera), found end of file"
    );
}

#[test]
fn columns_count_characters_and_tabs_as_one() {
    assert_eq!(
        parse_error(&format!("{CAMERA}\n\tBackground {{ color é 0 0 }}\n")),
        "s.txt:2:21: expected a number, found 'é'"
    );
    assert_eq!(
        parse_error(&format!("{CAMERA}\nBackground {{ color 0 0 0 }} Ñoño\n")),
        "s.txt:2:28: expected a scene block (OrthographicCamera, PerspectiveCamera, Background, \
         Lights, Materials or Group), found 'Ñoño'"
    );
}

// ---------------------------------------------------------------------------------------------
// Files: scene bytes and meshes

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn load_error(path: &Path) -> String {
    match Scene::load(path) {
        Ok(_) => panic!("{} loaded, but an error was expected", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_scene_that_is_not_utf8() {
    let dir = tempfile::tempdir().unwrap();
    // Valid "éé", then two bytes that are not UTF-8: the column counts characters, not bytes.
    let mut bytes = format!("{CAMERA}\nBackground {{ color 0 \u{e9}\u{e9}").into_bytes();
    bytes.extend_from_slice(b"\xff\xfe 0 }\n");
    let path = write(dir.path(), "s.txt", &bytes);
    assert_eq!(
        load_error(&path),
        format!(
            "{}:2:24: expected UTF-8 text, found byte 0xff",
            path.display()
        )
    );
}

#[test]
fn a_scene_file_that_does_not_exist() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing.txt");
    let message = load_error(&path);
    assert!(
        message.starts_with(&format!("{}: cannot read: ", path.display())),
        "{message}"
    );
}

const MESH_GROUP: &str = "Group { numObjects 1 MaterialIndex 0 TriangleMesh { obj_file FILE } }";

#[test]
fn a_mesh_file_that_does_not_exist() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "s.txt",
        with_group(&MESH_GROUP.replace("FILE", "nothere.obj")).as_bytes(),
    );
    // Both places are named: beside the scene, then the working directory.
    assert_eq!(
        load_error(&scene),
        format!(
            "{}:3:38: cannot open mesh file 'nothere.obj': looked for '{}' and 'nothere.obj'",
            scene.display(),
            dir.path().join("nothere.obj").display()
        )
    );
    // An absolute name is looked for in one place only.
    let absolute = dir.path().join("gone.obj");
    let scene = write(
        dir.path(),
        "s.txt",
        with_group(&MESH_GROUP.replace("FILE", &absolute.display().to_string())).as_bytes(),
    );
    assert_eq!(
        load_error(&scene),
        format!(
            "{}:3:38: cannot open mesh file '{}': looked for '{}'",
            scene.display(),
            absolute.display(),
            absolute.display()
        )
    );
}

#[test]
fn a_missing_mesh_of_a_scene_in_the_working_directory_names_one_place() {
    // `s.txt` lies in the working directory, so beside it and the working directory are one.
    assert_eq!(
        build_error(&with_group(&MESH_GROUP.replace("FILE", "nothere.obj"))),
        "s.txt:3:38: cannot open mesh file 'nothere.obj': looked for 'nothere.obj'"
    );
}

#[test]
fn a_malformed_mesh_names_the_obj_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "s.txt",
        with_group(&MESH_GROUP.replace("FILE", "bad.obj")).as_bytes(),
    );
    let obj = write(
        dir.path(),
        "bad.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
    );
    assert_eq!(
        load_error(&scene),
        format!(
            "{}:4:7: expected a vertex index from 1 to 3 (or -3 to -1), found '4'",
            obj.display()
        )
    );
    write(dir.path(), "bad.obj", b"v 0 0 0\nv 1 0 nope\n");
    assert_eq!(
        load_error(&scene),
        format!("{}:2:7: expected a number, found 'nope'", obj.display())
    );
    // Bytes that are not UTF-8 are shown as escapes, not as replacement characters.
    write(dir.path(), "bad.obj", b"v 0 0 0\nv 1 0 \xff\n");
    assert_eq!(
        load_error(&scene),
        format!("{}:2:7: expected a number, found '\\xff'", obj.display())
    );
}

// ---------------------------------------------------------------------------------------------
// Deep nesting: the parser keeps its own stack

const DEPTH: usize = 100_000;

fn nested(open: &str) -> String {
    let mut text = format!("{CAMERA}\n{MATERIAL}\nGroup {{ numObjects 1 MaterialIndex 0\n");
    text.reserve(DEPTH * (open.len() + 2) + 64);
    for _ in 0..DEPTH {
        text.push_str(open);
        text.push('\n');
    }
    text.push_str("Sphere { center 0 0 0 radius 1 }\n");
    for _ in 0..DEPTH {
        text.push_str("}\n");
    }
    text.push_str("}\n");
    text
}

/// Runs `f` on a thread with a 256 KiB stack: far too little for one native frame per level.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .expect("the parser overflowed a small stack")
}

#[test]
fn deeply_nested_transforms_parse_on_a_small_stack() {
    let description = on_small_stack(|| {
        parse_scene(Path::new("s.txt"), &nested("Transform { Translate 0 0 0")).unwrap()
    });
    assert_eq!(description.transforms.len(), DEPTH);
    assert_eq!(description.objects.len(), 1);
    assert_eq!(description.objects[0].transform, Some(DEPTH as u32 - 1));
}

#[test]
fn deeply_nested_groups_parse_on_a_small_stack() {
    let description = on_small_stack(|| {
        parse_scene(Path::new("s.txt"), &nested("Group { numObjects 1")).unwrap()
    });
    assert!(description.transforms.is_empty());
    assert_eq!(description.objects.len(), 1);
}

#[test]
fn an_error_deep_inside_nesting_is_reported_on_a_small_stack() {
    let mut text = nested("Transform { Translate 0 0 0");
    text.truncate(text.len() - 4); // the root Group's brace and the last Transform's
    let message = on_small_stack(move || parse_error(&text));
    assert_eq!(
        message,
        format!(
            "s.txt:{}:1: expected '}}', found end of file",
            4 + 2 * DEPTH
        )
    );
}

// ---------------------------------------------------------------------------------------------
// Shapes that a Transform carries beyond the bound

#[test]
fn shapes_placed_beyond_1e9_are_refused() {
    // Each number is within bounds; the shape, once placed, is not. The error points at it.
    assert_eq!(
        build_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Sphere { center 8e8 0 0 radius 5e8 } }"
        )),
        "s.txt:3:38: expected a sphere between -1e9 and 1e9 on every axis once placed in the \
         world, found one that reaches 1.3e9"
    );
    assert_eq!(
        build_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { Scale 1 1e5 1 \
             Sphere { center 0 0 0 radius 2e4 } } }"
        )),
        "s.txt:3:64: expected a sphere between -1e9 and 1e9 on every axis once placed in the \
         world, found one that reaches 2e9"
    );
    assert_eq!(
        build_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { UniformScale 1e5 \
             Triangle { vertex0 0 0 0 vertex1 1e5 0 0 vertex2 0 1 0 } } }"
        )),
        "s.txt:3:67: expected a triangle between -1e9 and 1e9 on every axis once placed in the \
         world, found one that reaches 1e10"
    );
    // A short normal divides the offset: this plane lies 1.6e9 from the origin.
    assert_eq!(
        build_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Plane { normal 0.5 0 0 offset 8e8 } }"
        )),
        "s.txt:3:38: expected a plane at most 1e9 from the origin once placed in the world, \
         found one 1.6e9 from it"
    );
    assert_eq!(
        build_error(&with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { Scale 1 1e9 1 \
             Plane { normal 0 1 0 offset -2 } } }"
        )),
        "s.txt:3:64: expected a plane at most 1e9 from the origin once placed in the world, \
         found one 2e9 from it"
    );
    // A mesh: its box, placed, is what counts.
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "cube.obj",
        b"v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nf 1 2 3 4\n",
    );
    let scene = write(
        dir.path(),
        "s.txt",
        with_group(
            "Group { numObjects 1 MaterialIndex 0 Transform { Translate 5e8 0 0 UniformScale 9e8 \
             TriangleMesh { obj_file cube.obj } } }",
        )
        .as_bytes(),
    );
    assert_eq!(
        load_error(&scene),
        format!(
            "{}:3:85: expected a mesh between -1e9 and 1e9 on every axis once placed in the \
             world, found one that reaches 1.4e9",
            scene.display()
        )
    );
}

#[test]
fn a_mesh_coordinate_beyond_1e9_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "s.txt",
        with_group(&MESH_GROUP.replace("FILE", "big.obj")).as_bytes(),
    );
    let obj = write(
        dir.path(),
        "big.obj",
        b"v 0 0 0\nv 1 0 3e38\nv 0 1 0\nf 1 2 3\n",
    );
    assert_eq!(
        load_error(&scene),
        format!(
            "{}:2:7: expected a number between -1e9 and 1e9, found '3e38'",
            obj.display()
        )
    );
}

// ---------------------------------------------------------------------------------------------
// Rules that are not errors: what raycast renders

fn render_scene(scene: &Scene, size: u32) -> raycast::Rendered {
    let settings = raycast::RenderSettings {
        width: size,
        height: size,
        colour: true,
        normals: true,
        depth: Some((0.0, 20.0)),
        trace: raycast::trace::TraceSettings::default(),
        progress: false,
        counter: None,
        stop: None,
        sampling: Default::default(),
        keep_film: false,
    };
    raycast::render::render(scene, &settings)
}

/// Every hit of the rays through the pixel centres of a `size`² picture: none may carry a
/// NaN or infinite t, or a normal that is not of unit length (NaN would become a black pixel).
fn assert_hits_are_finite(scene: &Scene, size: u32) -> usize {
    let mut hits = 0;
    for j in 0..size {
        for i in 0..size {
            let (u, v) = raycast::camera::pixel_to_screen(i, j, size, size);
            let ray = scene.camera.ray(u, v);
            if let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) {
                hits += 1;
                assert!(
                    hit.t.is_finite() && (hit.normal.length() - 1.0).abs() < 1e-4,
                    "pixel ({i}, {j}): t {} normal {}",
                    hit.t,
                    hit.normal
                );
            }
        }
    }
    hits
}

#[test]
fn zero_area_triangles_are_never_hit() {
    const BLUE: &str = "Background { color 0 0 1 }";
    // A 1×1 picture samples the very centre, where the tiny triangle's corner is: it was hit,
    // with a NaN normal, and drawn red.
    let camera = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 1 }";
    for triangle in [
        "Triangle { vertex0 0 0 0 vertex1 1e-20 0 0 vertex2 0 1e-20 0 }",
        "Triangle { vertex0 -1e-20 -1e-20 0 vertex1 1e-20 -1e-20 0 vertex2 0 1e-20 0 }",
        "Triangle { vertex0 -1 0 0 vertex1 0 0 0 vertex2 1 0 0 }",
        "Triangle { vertex0 0 0 0 vertex1 0 0 0 vertex2 0 1 0 }",
    ] {
        let text = format!(
            "{camera}\n{BLUE}\n{MATERIAL}\nGroup {{ numObjects 1 MaterialIndex 0 {triangle} }}\n"
        );
        let raycast::scene::Loaded { scene, stats } =
            Scene::from_description_with_stats(&parse_scene(Path::new("s.txt"), &text).unwrap())
                .unwrap();
        assert_eq!(stats.world.triangles, 0, "{triangle}");
        let rendered = render_scene(&scene, 1);
        assert_eq!(rendered.colour.unwrap().pixels, [[0, 0, 255]], "{triangle}");
        assert_eq!(rendered.normals.unwrap().pixels, [[0, 0, 0]], "{triangle}");
    }
    // In a mesh too: the flat faces are left out, the others stay.
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "m.obj",
        b"v 0 0 0\nv 1e-20 0 0\nv 0 1e-20 0\nv 1 1 0\nv 2 2 0\nv 0 1 0\n\
          f 1 2 3\nf 1 4 5\nf 1 4 6\n",
    );
    let scene = write(
        dir.path(),
        "s.txt",
        format!(
            "{camera}\n{BLUE}\n{MATERIAL}\n\
             Group {{ numObjects 1 MaterialIndex 0 TriangleMesh {{ obj_file m.obj }} }}\n"
        )
        .as_bytes(),
    );
    let raycast::scene::Loaded { scene, stats } = Scene::load_with_stats(&scene).unwrap();
    assert_eq!(stats.world.triangles, 1);
    assert_eq!(
        render_scene(&scene, 1).colour.unwrap().pixels,
        [[255, 0, 0]]
    );
}

#[test]
fn mirroring_transforms_keep_front_faces_and_normals() {
    // No lights: front faces are their flat colour, back faces black. Mirrored in x, every shape
    // must give the mirror image: a triangle that faced the camera still does, and so does the
    // outside of the cube and of the sphere.
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "cube.obj",
        b"v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
          f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n",
    );
    let shapes = "Group { numObjects 3\n\
        MaterialIndex 0 Triangle { vertex0 1 -3 0 vertex1 3 -3 0 vertex2 2 -1 0 }\n\
        MaterialIndex 1 Transform { Translate 2 2 0 YRotate 30 XRotate 20 UniformScale 0.8 \
          TriangleMesh { obj_file cube.obj } }\n\
        MaterialIndex 2 Transform { Translate -2 0 0 Scale 1 1.5 0.5 \
          Sphere { center 0 0 0 radius 1 } } }";
    let scene = |group: &str| {
        let text = format!(
            "PerspectiveCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 angle 45 }}\n\
             Background {{ color 0 0 0.2 }}\n\
             Materials {{ numMaterials 3 Material {{ diffuseColor 1 0 0 }} \
             Material {{ diffuseColor 0 1 0 }} Material {{ diffuseColor 1 1 0 }} }}\n\
             Group {{ numObjects 1 MaterialIndex 0 {group} }}\n"
        );
        let path = write(dir.path(), "s.txt", text.as_bytes());
        Scene::load(&path).unwrap()
    };
    let plain = scene(shapes);
    let mirrored = scene(&format!("Transform {{ Scale -1 1 1 {shapes} }}"));
    const SIZE: u32 = 64;
    assert!(assert_hits_are_finite(&mirrored, SIZE) > 500);
    let (a, b) = (render_scene(&plain, SIZE), render_scene(&mirrored, SIZE));
    let flipped =
        |image: &raycast::Image, i: u32, j: u32| image.pixels[(j * SIZE + (SIZE - 1 - i)) as usize];
    let mut differing = 0;
    let mut black = 0;
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (ca, cb) = (a.colour.as_ref().unwrap(), b.colour.as_ref().unwrap());
            let (na, nb) = (a.normals.as_ref().unwrap(), b.normals.as_ref().unwrap());
            let pixel = cb.pixels[(j * SIZE + i) as usize];
            black += (pixel == [0, 0, 0]) as usize;
            if pixel != flipped(ca, i, j) || nb.pixels[(j * SIZE + i) as usize] != flipped(na, i, j)
            {
                differing += 1;
            }
        }
    }
    // A pixel centre exactly on a silhouette may round to either side.
    assert!(
        differing <= 3,
        "{differing} pixels differ from the mirror image"
    );
    assert_eq!(black, 0, "a back face (black) is showing");
}

/// A sphere too small for single precision to give its surface a direction, hit dead centre:
/// its normal used to be NaN (a black pixel in the normals picture).
#[test]
fn surfaces_too_small_for_f32_still_face_the_ray() {
    let text = "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 }
        Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }
        Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }
        Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1e-7 } }";
    let description = raycast::parse::parse_scene(Path::new("tiny.txt"), text).unwrap();
    let scene = raycast::Scene::from_description(&description).unwrap();
    let settings = raycast::RenderSettings {
        width: 1,
        height: 1,
        colour: true,
        normals: true,
        depth: None,
        trace: raycast::trace::TraceSettings::default(),
        progress: false,
        counter: None,
        stop: None,
        sampling: Default::default(),
        keep_film: false,
    };
    let rendered = raycast::render::render(&scene, &settings);
    assert_eq!(rendered.colour.unwrap().pixels, vec![[255, 0, 0]]);
    assert_eq!(rendered.normals.unwrap().pixels, vec![[0, 0, 255]]);
}

/// SCENE_FORMAT.md §7: the current material is global to the parser, so it carries from one
/// top-level Group into a later one that replaces it.
#[test]
fn a_second_group_keeps_the_current_material() {
    let text = format!(
        "{CAMERA}\nMaterials {{ numMaterials 2 Material {{ }} Material {{ }} }}\n\
         Group {{ numObjects 1 MaterialIndex 1 Sphere {{ center 5 0 0 radius 1 }} }}\n\
         Group {{ numObjects 1 Sphere {{ center 0 0 0 radius 1 }} }}"
    );
    let description = parse_scene(Path::new("s.txt"), &text).unwrap();
    assert_eq!(description.objects.len(), 1);
    assert_eq!(description.objects[0].material, 1);
}

/// Transformation values are read in f64 like the matrices they build: `Scale 0.1 0.1 0.1`
/// and `UniformScale 0.1` are the same transformation.
#[test]
fn transform_values_keep_full_precision() {
    let matrix_of = |op: &str| {
        let text = format!(
            "{CAMERA}\n{MATERIAL}\nGroup {{ numObjects 1 MaterialIndex 0 \
             Transform {{ {op} Sphere {{ center 0 0 0 radius 1 }} }} }}"
        );
        parse_scene(Path::new("s.txt"), &text).unwrap().transforms[0]
    };
    assert_eq!(
        matrix_of("Scale 0.1 0.1 0.1"),
        matrix_of("UniformScale 0.1")
    );
}

// ---------------------------------------------------------------------------------------------
// Assignment 6's solid textures

/// The message for a third material `texture` after a white and a red Phong material.
fn texture_error(texture: &str) -> String {
    parse_error(&format!(
        "{CAMERA}\nMaterials {{ numMaterials 3 Material {{ }} Material {{ diffuseColor 1 0 0 }} {texture} }}\n"
    ))
}

#[test]
fn textures_in_the_course_grammar() {
    use raycast::parse::description::{MaterialSpec, Pattern};
    let (materials, _) = materials_and_lights(
        "Materials { numMaterials 6 Material { } Material { diffuseColor 1 0 0 }
            Checkerboard { materialIndex 0 materialIndex 1 }
            Noise { Transform { UniformScale 2 Translate 1 0 0 } materialIndex 1 materialIndex 0
                octaves 4 }
            Marble { materialIndex 2 materialIndex 3 octaves 0 frequency 3 amplitude -2.5 }
            Wood { Transform { ZRotate 90 } materialIndex 4 materialIndex 0 octaves 5
                frequency 7 amplitude 2 } }",
    );
    let texture = |i: usize| match materials[i] {
        MaterialSpec::Texture(t) => t,
        other => panic!("{other:?}"),
    };
    assert_eq!(texture(2).pattern, Pattern::Checkerboard);
    assert_eq!(texture(2).materials, [0, 1]);
    assert_eq!(texture(2).to_texture, glam::DMat4::IDENTITY);
    assert_eq!(texture(3).pattern, Pattern::Noise { octaves: 4 });
    assert_eq!(texture(3).materials, [1, 0]);
    // The ops compose as an object Transform's: the one listed last applies first.
    let p = texture(3)
        .to_texture
        .transform_point3(glam::DVec3::new(1.0, 1.0, 1.0));
    assert_eq!(p, glam::DVec3::new(4.0, 2.0, 2.0));
    assert_eq!(
        texture(4).pattern,
        Pattern::Marble {
            octaves: 0,
            frequency: 3.0,
            amplitude: -2.5
        }
    );
    assert_eq!(texture(4).materials, [2, 3]);
    assert!(matches!(
        texture(5).pattern,
        Pattern::Wood { octaves: 5, .. }
    ));
}

#[test]
fn texture_mistakes() {
    assert_eq!(
        texture_error("Checkerboard { materialIndex 0 materialIndex 2 }"),
        "s.txt:2:118: expected a material index from 0 to 1 (a texture uses materials listed \
         before it), found '2', the texture itself"
    );
    assert_eq!(
        texture_error("Checkerboard { materialIndex 0 materialIndex 3 }"),
        "s.txt:2:118: expected a material index from 0 to 1 (a texture uses materials listed \
         before it), found '3'"
    );
    assert_eq!(
        parse_error(&format!(
            "{CAMERA}\nMaterials {{ numMaterials 1 Checkerboard {{ materialIndex 0 materialIndex 0 }} }}\n"
        )),
        "s.txt:2:57: expected a material listed before this texture (it is the first material, \
         so there is none), found '0', the texture itself"
    );
    assert_eq!(
        texture_error("Checkerboard { materialIndex 1 }"),
        "s.txt:2:104: expected 'materialIndex', found '}'"
    );
    assert_eq!(
        texture_error("Checkerboard { materialIndex 0 materialIndex 1 octaves 3 }"),
        "s.txt:2:120: expected '}', found 'octaves'"
    );
    assert_eq!(
        texture_error("Noise { materialIndex 0 materialIndex 1 }"),
        "s.txt:2:113: expected 'octaves', found '}'"
    );
    for octaves in ["-1", "31", "1e9", "two"] {
        assert_eq!(
            texture_error(&format!(
                "Noise {{ materialIndex 0 materialIndex 1 octaves {octaves} }}"
            )),
            format!("s.txt:2:121: expected a number of octaves from 0 to 30, found '{octaves}'")
        );
    }
    // The fields come in the course's fixed order.
    assert_eq!(
        texture_error(
            "Marble { materialIndex 0 materialIndex 1 octaves 3 amplitude 2 frequency 1 }"
        ),
        "s.txt:2:124: expected 'frequency', found 'amplitude'"
    );
    assert_eq!(
        texture_error("Noise { octaves 2 materialIndex 0 materialIndex 1 }"),
        "s.txt:2:81: expected Transform or materialIndex, found 'octaves'"
    );
    // A texture's Transform holds ops only.
    assert_eq!(
        texture_error(
            "Wood { Transform { Scale 1 2 1 Sphere { center 0 0 0 radius 1 } } \
             materialIndex 0 materialIndex 1 octaves 3 frequency 1 amplitude 2 }"
        ),
        "s.txt:2:104: expected a transformation (Scale, UniformScale, Translate, XRotate, \
         YRotate, ZRotate, Rotate or Matrix) or '}' (a texture's Transform holds no object), \
         found 'Sphere'"
    );
    assert_eq!(
        texture_error(
            "Noise { Transform { UniformScale 0 } materialIndex 0 materialIndex 1 octaves 2 }"
        ),
        "s.txt:2:106: expected an invertible transformation, found one that flattens space (its \
         scales multiply to zero)"
    );
    assert_eq!(
        texture_error(
            "Noise { Transform { UniformScale 1e5 UniformScale 1e5 } materialIndex 0 \
             materialIndex 1 octaves 2 }"
        ),
        "s.txt:2:81: expected a texture transformation whose matrix has entries between -1e9 \
         and 1e9, found an entry of 1e10"
    );
}

#[test]
fn textures_nest_at_most_eight_deep() {
    let chain = |levels: usize| {
        let mut materials = vec!["Material { }".to_string()];
        materials.extend(
            (0..levels).map(|i| format!("Checkerboard {{ materialIndex {i} materialIndex 0 }}")),
        );
        format!(
            "{CAMERA}\nMaterials {{ numMaterials {} {} }}\nGroup {{ numObjects 0 }}\n",
            materials.len(),
            materials.join(" ")
        )
    };
    assert!(parse_scene(Path::new("s.txt"), &chain(8)).is_ok());
    let error = parse_error(&chain(9));
    assert!(
        error.ends_with("expected textures nested at most 8 deep, found one nested 9 deep"),
        "{error}"
    );
}

// ---------------------------------------------------------------------------------------------
// Descriptions built in code meet the parser's rules

#[test]
fn a_description_built_in_code_is_held_to_the_files_rules() {
    use glam::Vec3;
    use raycast::SceneBuilder;
    use raycast::parse::description::{CameraSpec, LightSpec, MaterialSpec, PhongSpec, Shape};
    let camera = CameraSpec::orthographic(Vec3::new(0.0, 0.0, 10.0), Vec3::NEG_Z, Vec3::Y, 5.0);
    let base = || SceneBuilder::new(camera).material(MaterialSpec::Phong(PhongSpec::default()));
    let error = |builder: SceneBuilder| builder.build().unwrap_err().to_string();
    let sphere = |radius| Shape::Sphere {
        center: Vec3::ZERO,
        radius,
    };
    assert_eq!(
        error(base().object(sphere(-1.0), 0)),
        "<scene built in code>: object 0: expected a positive radius, found '-1'"
    );
    assert_eq!(
        error(base().object(sphere(1.0), 0).object(sphere(1.0), 99)),
        "<scene built in code>: object 1: expected material index 0 (the scene has 1 \
         material), found '99'"
    );
    assert_eq!(
        error(base().object(sphere(f32::NAN), 0)),
        "<scene built in code>: object 0: expected a positive radius, found 'NaN'"
    );
    assert_eq!(
        error(base().object(
            Shape::Plane {
                normal: Vec3::ZERO,
                offset: 1.0
            },
            0
        )),
        "<scene built in code>: object 0: expected a plane normal of non-zero length, found \
         '0 0 0'"
    );
    assert_eq!(
        error(base().light(LightSpec::directional(Vec3::ZERO, Vec3::ONE))),
        "<scene built in code>: expected a direction of non-zero length for light 0, found \
         '0 0 0'"
    );
    let sideways = CameraSpec::perspective(Vec3::ZERO, Vec3::Y, Vec3::Y, 30.0);
    assert_eq!(
        error(SceneBuilder::new(sideways)),
        "<scene built in code>: expected an up vector that is not parallel to the direction \
         for the camera, found '0 1 0'"
    );
    let wide = CameraSpec::perspective(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 180.0);
    assert_eq!(
        error(SceneBuilder::new(wide)),
        "<scene built in code>: expected an angle between 0 and 180 degrees for the camera, \
         found '180'"
    );
    // A parsed description changed by hand is checked the same way.
    let mut description = parse_scene(
        Path::new("s.txt"),
        &with_group("Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }"),
    )
    .unwrap();
    description.objects[0].material = 7;
    assert_eq!(
        Scene::from_description(&description)
            .unwrap_err()
            .to_string(),
        "s.txt:3:38: expected material index 0 (the scene has 1 material), found '7'"
    );
}

#[test]
fn an_angle_that_single_precision_rounds_to_zero_is_refused() {
    assert_eq!(
        parse_error("PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 1e-46 }\n"),
        "s.txt:1:67: expected an angle between 0 and 180 degrees, found '1e-46'"
    );
}

#[test]
fn a_scene_saved_by_notepad_reads_as_the_same_scene() {
    // Notepad on Windows writes UTF-8 with a byte-order mark and CRLF line ends.
    let text =
        with_group("Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }");
    let notepad = format!("\u{feff}{}", text.replace('\n', "\r\n"));
    let plain = parse_scene(Path::new("s.txt"), &text).unwrap();
    let saved = raycast::parse::parse_scene_bytes(Path::new("s.txt"), notepad.as_bytes())
        .expect("a scene saved by Notepad should parse");
    assert_eq!(format!("{saved:?}"), format!("{plain:?}"));
}

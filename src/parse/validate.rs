//! The rules every scene description must keep, whoever made it: the parser, which checks the
//! same rules word by word as it reads (pointing at the word), or a program that builds the
//! description in code. `Scene::from_description` checks them all here, so that a description
//! the parser would refuse cannot reach the renderer another way, and is refused in the same
//! words.

use glam::{DMat4, Vec3};

use super::description::{
    CameraSpec, LightSpec, MaterialSpec, Pattern, PhongSpec, Projection, SceneDescription, Shape,
    TextureSpec,
};
use crate::error::{Diagnostic, Span};
use crate::parse::{MAX_MAGNITUDE, MAX_OCTAVES, MAX_TEXTURE_DEPTH, NUMBER_IN_RANGE, show_vector};

/// Checks `description`; the first rule broken is the error. Camera, lights and materials have
/// no place in the description, so their errors name the item instead of a line.
pub fn validate(description: &SceneDescription) -> Result<(), Diagnostic> {
    let error = |span: Span, expected: &str, found: String| {
        Diagnostic::expected(&description.path, span, expected, &found)
    };
    let nowhere = Span::default();
    camera(&description.camera).map_err(|(expected, found)| {
        error(nowhere, &format!("{expected} for the camera"), found)
    })?;
    for (name, colour) in [
        ("background colour", description.background),
        ("ambient light", description.ambient),
    ] {
        if !in_range(colour) {
            return Err(error(
                nowhere,
                &format!("{NUMBER_IN_RANGE} in the {name}"),
                show_vector(colour),
            ));
        }
    }
    for (i, light) in description.lights.iter().enumerate() {
        self::light(light).map_err(|(expected, found)| {
            error(nowhere, &format!("{expected} for light {i}"), found)
        })?;
    }
    let mut depths = Vec::new();
    for (i, material) in description.materials.iter().enumerate() {
        let depth = self::material(material, i, &depths).map_err(|(expected, found)| {
            error(nowhere, &format!("{expected} for material {i}"), found)
        })?;
        depths.push(depth);
    }
    for (i, matrix) in description.transforms.iter().enumerate() {
        transform(matrix).map_err(|(expected, found)| {
            error(nowhere, &format!("{expected} for transform {i}"), found)
        })?;
    }
    for (i, object) in description.objects.iter().enumerate() {
        // Without a place in a file, the message names the object.
        let error = |span: Span, expected: &str, found: String| {
            let expected = if span.line == 0 {
                format!("object {i}: expected {expected}")
            } else {
                format!("expected {expected}")
            };
            Diagnostic::new(
                &description.path,
                span,
                format!("{expected}, found {found}"),
            )
        };
        let materials = description.materials.len();
        if object.material as usize >= materials {
            let expected = material_index_expected(materials);
            return Err(error(
                object.span,
                &expected,
                format!("'{}'", object.material),
            ));
        }
        if let Some(t) = object.transform
            && t as usize >= description.transforms.len()
        {
            let n = description.transforms.len();
            return Err(error(
                object.span,
                &format!("a transform index below {n} (the scene has {n} transforms)"),
                format!("'{t}'"),
            ));
        }
        shape(&object.shape).map_err(|(expected, found)| error(object.span, &expected, found))?;
    }
    Ok(())
}

/// What a rule wanted and what it found instead.
pub(crate) type Broken = (String, String);

fn in_range(v: Vec3) -> bool {
    v.is_finite() && f64::from(v.abs().max_element()) <= MAX_MAGNITUDE
}

fn number(x: f32) -> String {
    format!("'{x}'")
}

fn vector_in_range(v: Vec3) -> Result<(), Broken> {
    if in_range(v) {
        Ok(())
    } else {
        Err((NUMBER_IN_RANGE.to_string(), show_vector(v)))
    }
}

fn direction(v: Vec3) -> Result<(), Broken> {
    vector_in_range(v)?;
    if v.normalize_or_zero() == Vec3::ZERO {
        return Err(("a direction of non-zero length".into(), show_vector(v)));
    }
    Ok(())
}

fn camera(camera: &CameraSpec) -> Result<(), Broken> {
    vector_in_range(camera.center)?;
    direction(camera.direction)?;
    vector_in_range(camera.up)?;
    if !camera
        .direction
        .cross(camera.up)
        .normalize_or_zero()
        .is_normalized()
    {
        return Err((
            "an up vector that is not parallel to the direction".into(),
            show_vector(camera.up),
        ));
    }
    match camera.projection {
        Projection::Orthographic { size } if !(size > 0.0 && size.is_finite()) => {
            Err(("a positive size".into(), number(size)))
        }
        Projection::Perspective { angle }
            if !(angle > 0.0 && (f64::from(angle).to_radians() as f32) < std::f32::consts::PI) =>
        {
            Err(("an angle between 0 and 180 degrees".into(), number(angle)))
        }
        _ => Ok(()),
    }
}

fn light(light: &LightSpec) -> Result<(), Broken> {
    match *light {
        LightSpec::Directional { direction, color } => {
            self::direction(direction)?;
            vector_in_range(color)
        }
        LightSpec::Point {
            position,
            color,
            attenuation,
        } => {
            vector_in_range(position)?;
            vector_in_range(color)?;
            let terms = Vec3::from(attenuation);
            if !in_range(terms) || terms.min_element() < 0.0 {
                return Err(("attenuation terms of 0 or more".into(), show_vector(terms)));
            }
            if terms == Vec3::ZERO {
                return Err((
                    "attenuation with at least one term above 0 (1 0 0: no fall-off)".into(),
                    "'0 0 0', which would make the light infinitely bright".into(),
                ));
            }
            Ok(())
        }
    }
}

/// Checks material `own`; returns how deep its textures nest (0 for a Phong material).
fn material(material: &MaterialSpec, own: usize, depths: &[u32]) -> Result<u32, Broken> {
    match material {
        MaterialSpec::Phong(phong) => {
            let PhongSpec {
                diffuse,
                specular,
                exponent,
                reflective,
                transparent,
                index_of_refraction,
            } = *phong;
            for colour in [diffuse, specular, reflective, transparent] {
                vector_in_range(colour)?;
            }
            if !(exponent >= 0.0 && f64::from(exponent) <= MAX_MAGNITUDE) {
                return Err(("a specular exponent of 0 or more".into(), number(exponent)));
            }
            if !(index_of_refraction > 0.0 && f64::from(index_of_refraction) <= MAX_MAGNITUDE) {
                return Err((
                    "an index of refraction above 0".into(),
                    number(index_of_refraction),
                ));
            }
            Ok(0)
        }
        MaterialSpec::Texture(texture) => {
            for &m in &texture.materials {
                if m as usize >= own {
                    return Err((texture_material_expected(own), format!("'{m}'")));
                }
            }
            let (octaves, numbers) = match texture.pattern {
                Pattern::Checkerboard => (0, [0.0, 0.0]),
                Pattern::Noise { octaves } => (octaves, [0.0, 0.0]),
                Pattern::Marble {
                    octaves,
                    frequency,
                    amplitude,
                }
                | Pattern::Wood {
                    octaves,
                    frequency,
                    amplitude,
                } => (octaves, [frequency, amplitude]),
            };
            if octaves > MAX_OCTAVES {
                return Err((
                    format!("a number of octaves from 0 to {MAX_OCTAVES}"),
                    format!("'{octaves}'"),
                ));
            }
            if let Some(&x) = numbers
                .iter()
                .find(|x| x.is_nan() || x.abs() > MAX_MAGNITUDE)
            {
                return Err((NUMBER_IN_RANGE.into(), format!("'{x}'")));
            }
            transform(&texture.to_texture)?;
            texture_depth(texture, depths)
        }
    }
}

fn transform(matrix: &DMat4) -> Result<(), Broken> {
    let largest = matrix
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, &x| a.max(x.abs()));
    if !matrix.is_finite() || largest > MAX_MAGNITUDE {
        return Err((
            "a transformation whose matrix has entries between -1e9 and 1e9".into(),
            if matrix.is_finite() {
                format!("an entry of {largest:e}")
            } else {
                "an entry that is not a number".to_string()
            },
        ));
    }
    if matrix.row(3) != glam::DVec4::W {
        return Err((
            "a last row of '0 0 0 1' (raycast does only affine transformations)".into(),
            format!(
                "'{}'",
                matrix.row(3).to_array().map(|x| x.to_string()).join(" ")
            ),
        ));
    }
    if matrix.determinant() == 0.0 {
        return Err((
            "an invertible transformation".into(),
            "one that flattens space (a scale of zero)".into(),
        ));
    }
    Ok(())
}

fn shape(shape: &Shape) -> Result<(), Broken> {
    match shape {
        Shape::Sphere { center, radius } => {
            vector_in_range(*center)?;
            if !(*radius > 0.0 && f64::from(*radius) <= MAX_MAGNITUDE) {
                return Err(("a positive radius".into(), number(*radius)));
            }
            Ok(())
        }
        Shape::Plane { normal, offset } => {
            vector_in_range(*normal)?;
            if normal.normalize_or_zero() == Vec3::ZERO {
                return Err((
                    "a plane normal of non-zero length".into(),
                    show_vector(*normal),
                ));
            }
            // How far the plane lies is checked where it is placed in the world (the parser
            // divides the offset by the normal's length, which may carry it past 1e9).
            if offset.is_nan() {
                return Err(("a number".into(), number(*offset)));
            }
            Ok(())
        }
        Shape::Triangle { vertices } => vertices.iter().try_for_each(|&v| vector_in_range(v)),
        Shape::Mesh { file } => {
            if file.is_empty() {
                return Err(("a mesh file name".into(), "nothing".into()));
            }
            Ok(())
        }
    }
}

/// What a `MaterialIndex` of a scene of `count` materials must be (the parser's words too).
pub(crate) fn material_index_expected(count: usize) -> String {
    match count {
        0 => "no MaterialIndex (the scene has no materials)".to_string(),
        1 => "material index 0 (the scene has 1 material)".to_string(),
        n => format!(
            "a material index from 0 to {} (the scene has {n} materials)",
            n - 1
        ),
    }
}

/// What a texture's `materialIndex` must be, the texture being material `own`.
pub(crate) fn texture_material_expected(own: usize) -> String {
    match own {
        0 => "a material listed before this texture (it is the first material, so there is none)"
            .to_string(),
        1 => "material index 0 (a texture uses materials listed before it)".to_string(),
        n => format!(
            "a material index from 0 to {} (a texture uses materials listed before it)",
            n - 1
        ),
    }
}

/// How deep `texture` nests, its materials nesting `depths` deep; refused past
/// [`MAX_TEXTURE_DEPTH`].
pub(crate) fn texture_depth(texture: &TextureSpec, depths: &[u32]) -> Result<u32, Broken> {
    let depth = 1 + texture
        .materials
        .map(|m| depths[m as usize])
        .iter()
        .max()
        .unwrap_or(&0);
    if depth > MAX_TEXTURE_DEPTH {
        return Err((
            format!("textures nested at most {MAX_TEXTURE_DEPTH} deep"),
            format!("one nested {depth} deep"),
        ));
    }
    Ok(depth)
}

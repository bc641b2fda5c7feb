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
use crate::parse::{
    MAX_MAGNITUDE, MAX_OCTAVES, MAX_TEXTURE_DEPTH, NUMBER_IN_RANGE, show_number, show_vector,
};

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
        transformation(matrix, Placing::Object).map_err(|(expected, found)| {
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

// The rules of single values, each once, with the words its message says: the parser checks
// them as it reads (pointing at the word, and showing it as written), `validate` on descriptions
// made in code.

/// A size, radius or index of refraction.
pub(crate) fn is_positive(x: f32) -> bool {
    x > 0.0 && f64::from(x) <= MAX_MAGNITUDE
}
pub(crate) const POSITIVE_SIZE: &str = "a positive size";
pub(crate) const POSITIVE_RADIUS: &str = "a positive radius";
pub(crate) const POSITIVE_INDEX: &str = "an index of refraction above 0";

/// A specular exponent or an attenuation term.
pub(crate) fn is_not_negative(x: f32) -> bool {
    x >= 0.0 && f64::from(x) <= MAX_MAGNITUDE
}
pub(crate) const EXPONENT: &str = "a specular exponent of 0 or more";
pub(crate) const ATTENUATION_TERM: &str = "an attenuation term of 0 or more";

/// A point light whose attenuation terms are all zero would be infinitely bright.
pub(crate) fn attenuation_falls(terms: [f32; 3]) -> bool {
    terms != [0.0; 3]
}
pub(crate) const ATTENUATION: (&str, &str) = (
    "attenuation with at least one term above 0 (1 0 0: no fall-off)",
    "'0 0 0', which would make the light infinitely bright",
);

/// A direction, a plane's normal: a vector that has one (so it can be normalised).
pub(crate) fn has_direction(v: Vec3) -> bool {
    v.normalize_or_zero() != Vec3::ZERO
}
pub(crate) const DIRECTION: &str = "a direction of non-zero length";
pub(crate) const PLANE_NORMAL: &str = "a plane normal of non-zero length";

/// The camera's up vector must pick a way up across the view.
pub(crate) fn up_is_across(direction: Vec3, up: Vec3) -> bool {
    direction.cross(up).normalize_or_zero().is_normalized()
}
pub(crate) const UP: &str = "an up vector that is not parallel to the direction";

/// Also below 180 once in f32 radians: an angle that rounds up to π would turn the screen's
/// tangent negative and the picture upside down.
pub(crate) fn is_field_of_view(angle: f32) -> bool {
    angle > 0.0 && (f64::from(angle).to_radians() as f32) < std::f32::consts::PI
}
pub(crate) const ANGLE: &str = "an angle between 0 and 180 degrees";

/// What a texture's `octaves` must be.
pub(crate) fn octaves_expected() -> String {
    format!("a number of octaves from 0 to {MAX_OCTAVES}")
}

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
    if !has_direction(v) {
        return Err((DIRECTION.into(), show_vector(v)));
    }
    Ok(())
}

fn camera(camera: &CameraSpec) -> Result<(), Broken> {
    vector_in_range(camera.center)?;
    direction(camera.direction)?;
    vector_in_range(camera.up)?;
    if !up_is_across(camera.direction, camera.up) {
        return Err((UP.into(), show_vector(camera.up)));
    }
    match camera.projection {
        Projection::Orthographic { size } if !is_positive(size) => {
            Err((POSITIVE_SIZE.into(), number(size)))
        }
        Projection::Perspective { angle } if !is_field_of_view(angle) => {
            Err((ANGLE.into(), number(angle)))
        }
        _ => Ok(()),
    }
}

fn light(light: &LightSpec) -> Result<(), Broken> {
    match *light {
        LightSpec::Directional { direction, colour } => {
            self::direction(direction)?;
            vector_in_range(colour)
        }
        LightSpec::Point {
            position,
            colour,
            attenuation,
        } => {
            vector_in_range(position)?;
            vector_in_range(colour)?;
            if let Some(&term) = attenuation.iter().find(|&&t| !is_not_negative(t)) {
                return Err((ATTENUATION_TERM.into(), number(term)));
            }
            if !attenuation_falls(attenuation) {
                return Err((ATTENUATION.0.into(), ATTENUATION.1.into()));
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
            if !is_not_negative(exponent) {
                return Err((EXPONENT.into(), number(exponent)));
            }
            if !is_positive(index_of_refraction) {
                return Err((POSITIVE_INDEX.into(), number(index_of_refraction)));
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
                return Err((octaves_expected(), format!("'{octaves}'")));
            }
            if let Some(&x) = numbers
                .iter()
                .find(|x| x.is_nan() || x.abs() > MAX_MAGNITUDE)
            {
                return Err((NUMBER_IN_RANGE.into(), format!("'{x}'")));
            }
            transformation(&texture.to_texture, Placing::Texture)?;
            texture_depth(texture, depths)
        }
    }
}

/// What a transformation places, which decides the rules it keeps and how messages name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Placing {
    /// An object, by its Transform and the Transforms around it (object to world).
    Object,
    /// A texture's pattern (world to texture space).
    Texture,
}

/// What a last row other than `0 0 0 1` is refused as: a projective map, which the course's code
/// would drop without a word (it keeps only the upper three rows).
pub(crate) const AFFINE: &str =
    "a last row of '0 0 0 1' (raycast does only affine transformations)";

/// A transformation that maps space onto a plane, a line or a point, whether one scale is zero
/// or several multiply to zero in double precision.
pub(crate) fn singular() -> Broken {
    (
        "an invertible transformation".into(),
        "one that flattens space (its scales multiply to zero)".into(),
    )
}

/// The rules a transformation keeps: entries within [`MAX_MAGNITUDE`], affine, invertible, and,
/// for an object, an inverse within [`MAX_MAGNITUDE`] too, which keeps a ray carried into the
/// object's space finite (its origin and direction go through the inverse, its normal through
/// the inverse's transpose, and a direction shrunk too far would square to 0).
pub(crate) fn transformation(matrix: &DMat4, placing: Placing) -> Result<(), Broken> {
    let whose = |which: &str| match placing {
        Placing::Object => format!(
            "a transformation whose {which}, with the Transforms around it, has entries between \
             -1e9 and 1e9"
        ),
        Placing::Texture => {
            format!("a texture transformation whose {which} has entries between -1e9 and 1e9")
        }
    };
    if !matrix.is_finite() {
        return Err((whose("matrix"), "an entry that is not a number".into()));
    }
    let largest = largest_entry(matrix);
    if largest > MAX_MAGNITUDE {
        return Err((
            whose("matrix"),
            format!("an entry of {}", show_number(largest)),
        ));
    }
    if matrix.row(3) != glam::DVec4::W {
        return Err((
            AFFINE.into(),
            format!(
                "'{}'",
                matrix.row(3).to_array().map(|x| x.to_string()).join(" ")
            ),
        ));
    }
    let inverse = matrix.inverse();
    if matrix.determinant() == 0.0 || !inverse.is_finite() {
        return Err(singular());
    }
    if placing == Placing::Object {
        let largest = largest_entry(&inverse);
        if largest > MAX_MAGNITUDE {
            return Err((
                whose("inverse"),
                format!(
                    "an entry of {} (it shrinks space too much)",
                    show_number(largest)
                ),
            ));
        }
    }
    Ok(())
}

fn largest_entry(m: &DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0, |a, &x| a.max(x.abs()))
}

fn shape(shape: &Shape) -> Result<(), Broken> {
    match shape {
        Shape::Sphere { center, radius } => {
            vector_in_range(*center)?;
            if !is_positive(*radius) {
                return Err((POSITIVE_RADIUS.into(), number(*radius)));
            }
            Ok(())
        }
        Shape::Plane { normal, offset } => {
            vector_in_range(*normal)?;
            if !has_direction(*normal) {
                return Err((PLANE_NORMAL.into(), show_vector(*normal)));
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

//! The forms whose mistake is made while the scene file is read.

use raycast::parse::description::{LightSpec, MaterialSpec, SceneDescription, Shape};

/// The description as the student's reader leaves it, for the form named `form`.
pub(crate) fn read_as(form: &str, description: &mut SceneDescription) {
    match form {
        // Only the rays lose it: a normal is carried by the matrix's linear part alone.
        "rays_lose_the_translation" => {
            let placed: Vec<u32> = description
                .objects
                .iter()
                .filter_map(|object| object.transform)
                .collect();
            for index in placed {
                description.transforms[index as usize].w_axis = raycast::glam::DVec4::W;
            }
        }
        "colours_read_blue_first" => {
            let swap = |colour: &mut raycast::Vec3| {
                *colour = raycast::Vec3::new(colour.z, colour.y, colour.x)
            };
            swap(&mut description.background);
            swap(&mut description.ambient);
            for light in &mut description.lights {
                match light {
                    LightSpec::Directional { colour, .. } | LightSpec::Point { colour, .. } => {
                        swap(colour)
                    }
                }
            }
            for material in &mut description.materials {
                if let MaterialSpec::Phong(phong) = material {
                    for colour in [
                        &mut phong.diffuse,
                        &mut phong.specular,
                        &mut phong.reflective,
                        &mut phong.transparent,
                    ] {
                        swap(colour);
                    }
                }
            }
        }
        // (A scene without lights has its flat colours from a white ambient light the reader
        // sets itself.)
        "ambient_never_stored" if !description.lights.is_empty() => {
            description.ambient = raycast::Vec3::ZERO;
        }
        // `specularColor` read into the material, then the highlight weighed by another
        // colour where there is one.
        "highlight_of_the_diffuse_colour" | "highlight_left_white" => {
            for material in &mut description.materials {
                if let MaterialSpec::Phong(phong) = material
                    && phong.specular != raycast::Vec3::ZERO
                {
                    phong.specular = if form == "highlight_left_white" {
                        raycast::Vec3::ONE
                    } else {
                        phong.diffuse
                    };
                }
            }
        }
        // A mirror's (or glass's) ray weighed by the specular colour, where the material has a
        // mirror (or is glass).
        "mirror_of_the_specular_colour" => {
            for material in &mut description.materials {
                if let MaterialSpec::Phong(phong) = material
                    && phong.reflective != raycast::Vec3::ZERO
                {
                    phong.reflective = phong.specular;
                }
            }
        }
        "glass_of_the_specular_colour" => {
            for material in &mut description.materials {
                if let MaterialSpec::Phong(phong) = material
                    && phong.transparent != raycast::Vec3::ZERO
                {
                    phong.transparent = phong.specular;
                }
            }
        }
        "direction_read_reversed" => {
            for light in &mut description.lights {
                if let LightSpec::Directional { direction, .. } = light {
                    *direction = -*direction;
                }
            }
        }
        "plane_offset_negated" => {
            for object in &mut description.objects {
                if let Shape::Plane { offset, .. } = &mut object.shape {
                    *offset = -*offset;
                }
            }
        }
        _ => {}
    }
}

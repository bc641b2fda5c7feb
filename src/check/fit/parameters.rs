//! Numbers of the stages past the first ray, fitted one family at a time: how near shadow and
//! secondary rays start to their surface (a t along the ray, or a distance along the normal, up
//! to the course's largest allowed epsilon: nearer shadows and reflects the surface itself),
//! glass's index, the weight below which rays are cut off, the mirror direction's factor, the
//! power of the material's colour a mirror or glass ray's colour is weighed by, and how far the
//! filter reaches. Each family is one number searched over its range by the render's distance
//! from the student's pictures; where it lands names its fault with the number
//! (an epsilon of 1e-6 is `shadow_acne` at 1e-6, whatever the formula that put it there).

use super::camera::Named;
use crate::check::faults::{
    FAULTS, LineScene, Plant, Planted, RayFault, SampleFault, bounces, glass_index, has_material,
    has_tinted_material,
};
use crate::sample::Sampler;

/// A stage's number as a family of renders.
struct Family {
    /// The fault its numbers name.
    fault: &'static str,
    /// The number's name in the report.
    parameter: &'static str,
    /// The range searched, evenly in the number's logarithm (or, for a range that holds 0 or
    /// negative numbers, in the number).
    range: (f64, f64),
    /// The number the course's render of the line has, where one has: a fit landing as close
    /// as that to it names nothing.
    course: fn(&LineScene) -> Option<f64>,
    /// Whether the family can change the line's pictures.
    applies: fn(&LineScene) -> bool,
    /// The render with the number.
    plant: fn(f32) -> Planted,
}

/// Whether the line traces shadow or secondary rays.
fn leaves_surfaces(line: &LineScene) -> bool {
    line.has_image() && (line.options.trace.shadows || line.options.trace.bounces > 0)
}

const FAMILIES: [Family; 9] = [
    Family {
        fault: "shadow_acne",
        parameter: "least t",
        range: (1e-9, 1e-3),
        course: |_| None,
        applies: leaves_surfaces,
        plant: |epsilon| Planted::Ray(RayFault::FixedStart(epsilon)),
    },
    Family {
        fault: "shadow_acne",
        parameter: "offset along the normal",
        range: (1e-9, 1e-3),
        course: |_| None,
        applies: leaves_surfaces,
        plant: |offset| Planted::Ray(RayFault::NormalOffset(offset)),
    },
    Family {
        fault: "refraction_index",
        parameter: "index",
        range: (0.25, 4.0),
        course: |line| glass_index(line).map(f64::from),
        applies: |line| glass_index(line).is_some(),
        plant: |index| Planted::Ray(RayFault::IndexAs(index)),
    },
    Family {
        fault: "reflection_direction",
        parameter: "factor of (d·n) n",
        range: (-4.0, 4.0),
        course: |_| Some(-2.0),
        applies: |line| bounces(line) && has_material(line, false),
        plant: |factor| Planted::Ray(RayFault::MirrorFactor(factor)),
    },
    Family {
        fault: "secondary_colour",
        parameter: "power of the reflective colour",
        range: (0.125, 8.0),
        course: |_| Some(1.0),
        applies: |line| bounces(line) && has_tinted_material(line, false),
        plant: |power| {
            Planted::Ray(RayFault::ColourPower {
                transparent: false,
                power,
            })
        },
    },
    Family {
        fault: "secondary_colour",
        parameter: "power of the transparent colour",
        range: (0.125, 8.0),
        course: |_| Some(1.0),
        applies: |line| bounces(line) && has_tinted_material(line, true),
        plant: |power| {
            Planted::Ray(RayFault::ColourPower {
                transparent: true,
                power,
            })
        },
    },
    Family {
        fault: "weight_cutoff",
        parameter: "weight",
        range: (1e-4, 0.5),
        course: |line| Some(f64::from(line.options.trace.cutoff_weight)),
        applies: bounces,
        plant: |weight| Planted::Ray(RayFault::CutoffAt(weight)),
    },
    Family {
        fault: "uniform_corners",
        parameter: "spread",
        range: (0.25, 4.0),
        course: |_| Some(1.0),
        applies: |line| matches!(line.options.sampling.sampler, Sampler::Uniform(n) if n > 1),
        plant: |by| Planted::Sample(SampleFault::UniformSpread(by)),
    },
    Family {
        fault: "filter_radius",
        parameter: "scale",
        range: (0.2, 5.0),
        course: |_| Some(1.0),
        applies: |line| !line.options.sampling.is_plain(),
        plant: |scale| Planted::Sample(SampleFault::FilterScale(scale)),
    },
];

/// Points of the first, even search over a range...
const GRID: usize = 13;
/// ...and halvings of the interval around the best of them.
const REFINE: usize = 8;
/// A number is taken at fewer significant digits where the render is no further than this
/// share from the pictures for it.
const ROUND_SHARE: f64 = 0.02;
/// A fit within this factor of the course's number is the course's.
const SAME: f64 = 1.02;

/// For each family that can change the line, the number whose render is least `distance` from
/// the pictures, with the faults it names, where it is nearer than the family's other numbers
/// by something (a family that changes nothing the pictures show names nothing).
pub fn fit_parameters<E>(
    line: &LineScene,
    mut distance: impl FnMut(Plant) -> Result<f64, E>,
) -> Result<Vec<(Plant, Named)>, E> {
    let mut fitted = Vec::new();
    for family in FAMILIES.iter().filter(|f| (f.applies)(line)) {
        let Some(fault) = FAULTS.iter().find(|f| f.name == family.fault) else {
            continue;
        };
        // Searched in the number's logarithm where the range is positive.
        let logarithmic = family.range.0 > 0.0;
        let (into, from): (fn(f64) -> f64, fn(f64) -> f64) = if logarithmic {
            (f64::ln, f64::exp)
        } else {
            (|x| x, |x| x)
        };
        let mut measure = |x: f64| distance(Plant::one((family.plant)(x as f32)));
        let (low, high) = (into(family.range.0), into(family.range.1));
        let step = (high - low) / (GRID - 1) as f64;
        let mut grid = Vec::with_capacity(GRID);
        for i in 0..GRID {
            let x = low + step * i as f64;
            grid.push((x, measure(from(x))?));
        }
        let worst = grid.iter().map(|&(_, d)| d).fold(0.0, f64::max);
        let best = (0..GRID)
            .min_by(|&a, &b| grid[a].1.total_cmp(&grid[b].1))
            .unwrap_or(0);
        // A family whose every number draws the same is no explanation.
        if grid[best].1 >= worst {
            continue;
        }
        // Halvings of the interval either side of the best point, toward the nearer half.
        let (mut at, mut value) = grid[best];
        let mut half = step;
        for _ in 0..REFINE {
            half /= 2.0;
            for x in [at - half, at + half] {
                let d = measure(from(x))?;
                if d < value {
                    (at, value) = (x, d);
                }
            }
        }
        // Where every number from the best on toward the course's draws as near (a grid of
        // samples clamped to the pixel's edge), the one nearest the course's: the least change
        // that explains the pictures.
        if let Some(course) = (family.course)(line).map(into) {
            let (mut inside, mut outside) = (at, course);
            for _ in 0..REFINE {
                let middle = (inside + outside) / 2.0;
                if measure(from(middle))? <= value {
                    inside = middle;
                } else {
                    outside = middle;
                }
            }
            at = inside;
        }
        // The number as a person would write it, where the render is as near for it: one
        // significant digit, a fraction of small numbers (4/3 of the radius), two or three digits.
        let mut number = from(at);
        let fraction = (1..=8u32).find_map(|d| {
            let n = (number * f64::from(d)).round();
            let close = n > 0.0 && (n / f64::from(d) / number - 1.0).abs() <= 0.02;
            close.then(|| n / f64::from(d))
        });
        let rounder = [Some(significant(number, 1)), fraction]
            .into_iter()
            .chain([2, 3].map(|digits| Some(significant(number, digits))))
            .flatten();
        // A rounding takes the number no further from the course's than a few hundredths of
        // it, past where it stopped.
        let no_further = |round: f64| {
            (family.course)(line).is_none_or(|course| {
                (round - number).abs() <= ROUND_SHARE * number.abs()
                    || (into(round) - into(course)).abs() <= (into(number) - into(course)).abs()
            })
        };
        for round in rounder.filter(|&round| no_further(round)) {
            if measure(round)? <= value * (1.0 + ROUND_SHARE) {
                number = round;
                break;
            }
        }
        if (family.course)(line).is_some_and(|course| {
            number * course > 0.0 && number / course <= SAME && course / number <= SAME
        }) {
            continue;
        }
        fitted.push((
            Plant::one((family.plant)(number as f32)),
            (vec![fault], vec![(family.parameter, number)]),
        ));
    }
    Ok(fitted)
}

/// `x` to `digits` significant digits.
fn significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits() {
        assert_eq!(significant(1.03e-6, 1), 1e-6);
        assert_eq!(significant(0.000_123_4, 2), 0.000_12);
        assert_eq!(significant(2.46, 2), 2.5);
        assert_eq!(significant(0.0, 2), 0.0);
    }

    fn line(args: &str, scene: &str) -> LineScene {
        let options = match crate::job::parse_args(args.split(' ').map(Into::into).collect()) {
            Ok(crate::job::Command::Render(options)) => *options,
            _ => panic!("a render's command line"),
        };
        let description =
            crate::parse::parse_scene(std::path::Path::new("scene.txt"), scene).unwrap();
        let scene = crate::scene::Scene::from_description(&description).unwrap();
        LineScene {
            options,
            description,
            scene,
        }
    }

    #[test]
    fn a_family_that_changes_nothing_names_nothing() {
        let line = line(
            "-input scene.txt -size 20 20 -output out.tga -shadows",
            "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }
             Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }
             Background { color 0 0 0 }
             Materials { numMaterials 1 PhongMaterial { diffuseColor 1 0 0 } }
             Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }",
        );
        let fitted = fit_parameters::<()>(&line, |_| Ok(1.0)).unwrap();
        assert!(fitted.is_empty());
        // A distance least at 1e-6 along the ray: the fit lands there, to one digit.
        let fitted = fit_parameters::<()>(&line, |plant| {
            Ok(match plant.first() {
                Planted::Ray(RayFault::FixedStart(e)) => (f64::from(e).log10() + 6.0).abs(),
                _ => 1.0,
            })
        })
        .unwrap();
        assert_eq!(fitted.len(), 1);
        let (faults, numbers) = &fitted[0].1;
        assert_eq!(faults[0].name, "shadow_acne");
        assert_eq!(numbers[..], [("least t", 1e-6)]);
    }

    #[test]
    fn a_flat_best_is_taken_at_its_end_nearest_the_course() {
        let line = line(
            "-input scene.txt -size 20 20 -output out.tga -uniform_samples 9 -box_filter 0.5",
            "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }
             Background { color 0 0 0 }
             Materials { numMaterials 1 PhongMaterial { diffuseColor 1 0 0 } }
             Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }",
        );
        // A grid from edge to edge of the pixel, its samples clamped inside it: every spread
        // from 1.5 on draws the same.
        let fitted = fit_parameters::<()>(&line, |plant| {
            Ok(match plant.first() {
                Planted::Sample(SampleFault::UniformSpread(by)) => (1.5 - f64::from(by)).max(0.0),
                _ => 1.0,
            })
        })
        .unwrap();
        assert_eq!(fitted.len(), 1);
        let (faults, numbers) = &fitted[0].1;
        assert_eq!(faults[0].name, "uniform_corners");
        assert_eq!(numbers[..], [("spread", 1.5)]);
    }

    #[test]
    fn a_family_of_negative_numbers_is_searched_evenly() {
        let line = line(
            "-input scene.txt -size 20 20 -output out.tga -bounces 2",
            "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }
             Background { color 0 0 0 }
             Materials { numMaterials 1
                 PhongMaterial { diffuseColor 1 0 0 reflectiveColor 0.5 0.5 0.5 } }
             Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }",
        );
        // The mirror direction d - (d·n) n: the factor -1, between the course's -2 and 0.
        let fitted = fit_parameters::<()>(&line, |plant| {
            Ok(match plant.first() {
                Planted::Ray(RayFault::MirrorFactor(factor)) => (f64::from(factor) + 1.0).abs(),
                _ => 1.0,
            })
        })
        .unwrap();
        let named: Vec<_> = fitted
            .iter()
            .map(|(_, (faults, numbers))| (faults[0].name, numbers.clone()))
            .collect();
        assert_eq!(
            named,
            [("reflection_direction", vec![("factor of (d·n) n", -1.0)])]
        );
    }
}

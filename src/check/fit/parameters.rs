//! Numbers of the stages past the first ray, fitted one family at a time: how far a camera
//! ray's search for the nearest hit starts (a finite "infinity"), how near shadow and
//! secondary rays start to their surface (a t along the ray, or a distance along the normal, up
//! to the course's largest allowed epsilon: nearer shadows and reflects the surface itself),
//! glass's index, the weight below which rays are cut off, the mirror direction's factor, the
//! power of the material's colour a mirror or glass ray's colour is weighed by, how far the
//! filter reaches, the epsilons by which a triangle test refuses hits (on the barycentric
//! coordinates, or on the determinant), and the power of a transformed object's stretch along
//! the ray that its t is measured with (0 the world's t; 1 the object space's, made unit). Each family is one number searched over its range by
//! the render's distance from the student's pictures; where it lands names its fault with the
//! number (an epsilon of 1e-6 is `shadow_acne` at 1e-6, whatever the formula that put it
//! there).

use super::camera::Named;
use crate::check::faults::{
    FAULTS, HitFault, LineScene, Plant, Planted, RayFault, SampleFault, bounces, glass_index,
    has_material, has_tinted_material, has_triangles, lengths_change,
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

const FAMILIES: [Family; 14] = [
    Family {
        fault: "t_limit",
        parameter: "limit",
        range: (0.5, 1e5),
        course: |_| None,
        applies: |line| line.has_traced_picture(),
        plant: |limit| Planted::Hit(HitFault::Limit(limit)),
    },
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
        fault: "uniform_corners",
        parameter: "offset",
        range: (-1.0, 1.0),
        course: |_| Some(0.0),
        applies: |line| matches!(line.options.sampling.sampler, Sampler::Uniform(n) if n > 1),
        plant: |by| Planted::Sample(SampleFault::UniformOffset(by)),
    },
    Family {
        fault: "triangle_epsilon",
        parameter: "edge_epsilon",
        range: (1e-6, 0.1),
        course: |_| None,
        applies: has_triangles,
        plant: |epsilon| Planted::Hit(HitFault::EdgeEpsilon(epsilon)),
    },
    Family {
        fault: "triangle_epsilon",
        parameter: "determinant_epsilon",
        range: (1e-9, 1.0),
        course: |_| None,
        applies: has_triangles,
        plant: |epsilon| Planted::Hit(HitFault::DeterminantEpsilon(epsilon)),
    },
    Family {
        fault: "object_space_t",
        parameter: "power of the object's stretch",
        range: (-2.0, 4.0),
        course: |_| Some(0.0),
        applies: |line| line.has_traced_picture() && lengths_change(line),
        plant: |power| Planted::Hit(HitFault::ObjectSpaceT(power)),
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

/// How a family's number maps to where it is searched, or back.
type Mapping = fn(f64) -> f64;

/// Points of the first, even search over a range...
const GRID: usize = 13;
/// ...and halvings of the interval around the best of them.
const REFINE: usize = 8;
/// A number is taken at fewer significant digits where the render is no further than this
/// share from the pictures for it.
const ROUND_SHARE: f64 = 0.02;
/// A fit within this factor of the course's number is the course's.
const SAME: f64 = 1.02;

/// For each family that can change the line, the numbers whose render is least `distance` from
/// the pictures, with the faults they name, where they are nearer than the family's other
/// numbers by something (a family that changes nothing the pictures show names nothing): the
/// alternatives to prove in turn, where the rows measured cannot tell several numbers apart.
pub fn fit_parameters<E>(
    line: &LineScene,
    mut distance: impl FnMut(Plant) -> Result<f64, E>,
) -> Result<Vec<Vec<(Plant, Named)>>, E> {
    let mut fitted = Vec::new();
    for family in FAMILIES.iter().filter(|f| (f.applies)(line)) {
        let Some(fault) = FAULTS.iter().find(|f| f.name == family.fault) else {
            continue;
        };
        // Searched in the number's logarithm where the range is positive.
        let logarithmic = family.range.0 > 0.0;
        let (into, from): (Mapping, Mapping) = if logarithmic {
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
        // The numbers either side of the best that draw as near over the rows measured: where
        // those rows cannot tell them apart (a search's limit between two rows' worth of a
        // horizon, a grid of samples clamped to the pixel's edge), any of them may be the one.
        let mut edge = |toward: f64| -> Result<f64, E> {
            let mut inside = at;
            let mut outside = (at + toward * step).clamp(low, high);
            if measure(from(outside))? <= value {
                return Ok(outside);
            }
            for _ in 0..REFINE {
                let middle = (inside + outside) / 2.0;
                if measure(from(middle))? <= value {
                    inside = middle;
                } else {
                    outside = middle;
                }
            }
            Ok(inside)
        };
        let flat = (from(edge(-1.0)?), from(edge(1.0)?));
        let course = (family.course)(line);
        // The course's own number among them: the family explains nothing.
        if course.is_some_and(|c| flat.0 <= c && c <= flat.1) {
            continue;
        }
        let mut numbers = Vec::new();
        // Nearest the course's first (the least change that explains the pictures), then the
        // roundest of them, then the best as a person would write it.
        if let Some(course) = course {
            let near = if course < flat.0 { flat.0 } else { flat.1 };
            numbers.push(written(near, value, Some(course), &mut measure)?);
        }
        numbers.extend(roundest_between(flat.0, flat.1));
        numbers.push(written(from(at), value, course, &mut measure)?);
        let mut tried: Vec<f64> = Vec::new();
        let mut alternatives = Vec::new();
        for number in numbers {
            let same_as_course = course.is_some_and(|course| {
                (number * course > 0.0 && number / course <= SAME && course / number <= SAME)
                    || (course == 0.0 && number.abs() < 1e-3)
            });
            if same_as_course || tried.contains(&number) {
                continue;
            }
            tried.push(number);
            alternatives.push((
                Plant::one((family.plant)(number as f32)),
                (vec![fault], vec![(family.parameter, number)]),
            ));
        }
        if !alternatives.is_empty() {
            fitted.push(alternatives);
        }
    }
    Ok(fitted)
}

/// `number` as a person would write it, where the render is as near for it (within
/// [`ROUND_SHARE`] of `value`) and it is no further from the `course`'s number than a few
/// hundredths of it: one significant digit, a fraction of small numbers (4/3 of the radius),
/// two or three digits.
fn written<E>(
    number: f64,
    value: f64,
    course: Option<f64>,
    measure: &mut impl FnMut(f64) -> Result<f64, E>,
) -> Result<f64, E> {
    let fraction = (1..=8u32).find_map(|d| {
        let n = (number * f64::from(d)).round();
        let close = n > 0.0 && (n / f64::from(d) / number - 1.0).abs() <= 0.02;
        close.then(|| n / f64::from(d))
    });
    let rounder = [Some(significant(number, 1)), fraction]
        .into_iter()
        .chain([2, 3].map(|digits| Some(significant(number, digits))))
        .flatten();
    let no_further = |round: f64| {
        course.is_none_or(|course| {
            (round - number).abs() <= ROUND_SHARE * number.abs()
                || (round - course).abs() <= (number - course).abs()
        })
    };
    for round in rounder.filter(|&round| no_further(round)) {
        if measure(round)? <= value * (1.0 + ROUND_SHARE) {
            return Ok(round);
        }
    }
    Ok(number)
}

/// The roundest numbers from `low` to `high`: those of the fewest significant digits (up to
/// three), at most four, the nearest their middle first.
fn roundest_between(low: f64, high: f64) -> Vec<f64> {
    if low <= 0.0 && 0.0 <= high {
        return vec![0.0];
    }
    let middle = (low + high) / 2.0;
    let magnitude = low.abs().max(high.abs()).log10().floor() as i32;
    for digits in 1..=3 {
        let exponent = magnitude - digits + 1;
        let step = 10f64.powi(exponent);
        // k / 10^n, not k × 0.1^n, so that 14 tenths is 1.4.
        let at = |k: i64| match exponent {
            e if e >= 0 => k as f64 * step,
            e => k as f64 / 10f64.powi(-e),
        };
        let (first, last) = ((low / step).ceil() as i64, (high / step).floor() as i64);
        if first <= last {
            let mut round: Vec<f64> = (first..=last).map(at).collect();
            round.sort_by(|a, b| (a - middle).abs().total_cmp(&(b - middle).abs()));
            round.truncate(4);
            return round;
        }
    }
    Vec::new()
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
    fn the_roundest_numbers_of_a_range() {
        // A search's limit the measured rows cannot place closer than 49.996 to 60.02: 50 and
        // 60 are as round, both are tried.
        assert_eq!(roundest_between(49.996, 60.02), [60.0, 50.0]);
        assert_eq!(roundest_between(1.38, 1.47), [1.4]);
        assert_eq!(roundest_between(-0.3, 0.2), [0.0]);
        assert_eq!(roundest_between(1.2345, 1.2346), Vec::<f64>::new());
    }

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
        let (faults, numbers) = &fitted[0][0].1;
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
        let (faults, numbers) = &fitted[0][0].1;
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
            .flatten()
            .map(|(_, (faults, numbers))| (faults[0].name, numbers.clone()))
            .collect();
        assert_eq!(
            named,
            [("reflection_direction", vec![("factor of (d·n) n", -1.0)])]
        );
    }
}

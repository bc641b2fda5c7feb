//! The least of a function of a few parameters, found by the Nelder–Mead simplex: no
//! derivatives, so it needs nothing of the function but its values, and a render's distance from
//! a student's picture has none to give. (A crate such as `argmin` does this and much more; one
//! method of forty lines is kept here instead of its dependency tree.)

/// A parameter of a fit: where the search starts, and how far its first steps go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    pub value: f64,
    pub step: f64,
}

/// The least value found and where: the parameters, and the function's value there.
#[derive(Debug, Clone, PartialEq)]
pub struct Least {
    pub at: Vec<f64>,
    pub value: f64,
}

// The simplex's moves: reflection, expansion, contraction and shrinking.
const REFLECT: f64 = 1.0;
const EXPAND: f64 = 2.0;
const CONTRACT: f64 = 0.5;
const SHRINK: f64 = 0.5;
/// The search ends once every corner is within this share of a first step of the best.
const SETTLED: f64 = 1e-3;

/// The parameters near `starts` where `value` is least, within `evaluations` calls; ends at
/// once on a value of 0 or below (nothing can be better) and on the first error.
pub fn minimise<E>(
    starts: &[Start],
    evaluations: usize,
    mut value: impl FnMut(&[f64]) -> Result<f64, E>,
) -> Result<Least, E> {
    let n = starts.len();
    // Corners in units of each parameter's step, from its start: one scale for every axis.
    let at = |z: &[f64]| -> Vec<f64> {
        z.iter()
            .zip(starts)
            .map(|(z, s)| s.value + z * s.step)
            .collect()
    };
    let calls = std::cell::Cell::new(0);
    let mut eval = |z: &[f64]| {
        calls.set(calls.get() + 1);
        value(&at(z)).map(|v| if v.is_nan() { f64::INFINITY } else { v })
    };
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let origin = vec![0.0; n];
    let first = eval(&origin)?;
    simplex.push((origin, first));
    for axis in 0..n {
        if simplex[0].1 <= 0.0 {
            break;
        }
        let mut corner = vec![0.0; n];
        corner[axis] = 1.0;
        let v = eval(&corner)?;
        simplex.push((corner, v));
    }
    loop {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let best = &simplex[0];
        let settled = simplex
            .iter()
            .all(|(z, _)| z.iter().zip(&best.0).all(|(a, b)| (a - b).abs() < SETTLED));
        if best.1 <= 0.0 || settled || simplex.len() <= n || calls.get() >= evaluations {
            break;
        }
        let worst = simplex[n].clone();
        let centroid: Vec<f64> = (0..n)
            .map(|i| simplex[..n].iter().map(|(z, _)| z[i]).sum::<f64>() / n as f64)
            .collect();
        let toward = |t: f64| -> Vec<f64> {
            centroid
                .iter()
                .zip(&worst.0)
                .map(|(c, w)| c + t * (c - w))
                .collect()
        };
        let reflected = toward(REFLECT);
        let r = eval(&reflected)?;
        if r < simplex[0].1 {
            let expanded = toward(EXPAND);
            let e = eval(&expanded)?;
            simplex[n] = if e < r { (expanded, e) } else { (reflected, r) };
        } else if r < simplex[n - 1].1 {
            simplex[n] = (reflected, r);
        } else {
            let contracted = if r < worst.1 {
                toward(CONTRACT * REFLECT)
            } else {
                toward(-CONTRACT)
            };
            let c = eval(&contracted)?;
            if c < worst.1.min(r) {
                simplex[n] = (contracted, c);
            } else {
                let best = simplex[0].0.clone();
                for corner in simplex.iter_mut().skip(1) {
                    let z: Vec<f64> = corner
                        .0
                        .iter()
                        .zip(&best)
                        .map(|(z, b)| b + SHRINK * (z - b))
                        .collect();
                    let v = eval(&z)?;
                    *corner = (z, v);
                }
            }
        }
    }
    let (z, v) = simplex
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("the simplex has its origin");
    Ok(Least {
        at: at(&z),
        value: v,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn starts(values: &[f64]) -> Vec<Start> {
        values
            .iter()
            .map(|&value| Start { value, step: 0.5 })
            .collect()
    }

    #[test]
    fn finds_the_least_of_a_bowl_off_its_start() {
        let least = minimise::<()>(&starts(&[0.0, 0.0, 0.0]), 500, |p| {
            Ok((p[0] - 0.5).powi(2) + 3.0 * (p[1] + 0.25).powi(2) + (p[2] - 1.2).abs())
        })
        .unwrap();
        for (got, want) in least.at.iter().zip([0.5, -0.25, 1.2]) {
            assert!((got - want).abs() < 2e-3, "{least:?}");
        }
    }

    #[test]
    fn ends_at_a_perfect_value_and_within_its_calls() {
        let mut calls = 0;
        let least = minimise::<()>(&starts(&[1.0, 1.0]), 1000, |p| {
            calls += 1;
            Ok(if p[0] == 1.0 { 0.0 } else { 1.0 })
        })
        .unwrap();
        assert_eq!((calls, least.value), (1, 0.0));
        let mut calls = 0;
        minimise::<()>(&starts(&[0.0, 0.0]), 20, |p| {
            calls += 1;
            Ok(-p[0].atan())
        })
        .unwrap();
        assert!(calls <= 20 + 3, "{calls}");
    }

    #[test]
    fn an_error_ends_the_search() {
        let result = minimise(&starts(&[0.0]), 100, |p| {
            if p[0] > 0.9 {
                Err("stopped")
            } else {
                Ok(2.0 - p[0])
            }
        });
        assert_eq!(result, Err("stopped"));
    }
}

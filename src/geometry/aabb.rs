//! Axis-aligned boxes: what the trees and the grid are built from.

use glam::Vec3A;

#[cfg(test)]
use super::Ray;

/// An axis-aligned box; the empty box has min = +inf and max = -inf so that growing it works.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The lowest corner: the least coordinate on each axis.
    pub min: Vec3A,
    /// The highest corner: the greatest coordinate on each axis.
    pub max: Vec3A,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The box of nothing: grown by a point, it becomes that point's box.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    /// The smallest box around `points`; [`Aabb::EMPTY`] for none.
    pub fn from_points(points: &[Vec3A]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }

    /// The box stretched to take in `p`.
    pub fn grow(self, p: Vec3A) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box around both boxes.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether `p` lies inside the box or on its sides.
    pub fn contains(&self, p: Vec3A) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Whether the box holds no point (min above max on some axis), as [`Aabb::EMPTY`] does.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Half the surface area, which is all the SAH needs; 0 for the empty box.
    pub fn half_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        self.half_area_unchecked()
    }

    /// [`Aabb::half_area`] for a box known not to be empty (the empty box gives NaN).
    #[inline]
    pub fn half_area_unchecked(&self) -> f32 {
        let d = self.max - self.min;
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// Where the ray enters the box within [t_min, t_max], if it meets it there. (The trees test
    /// four boxes at once; this one-box form is the tests' reference.)
    #[cfg(test)]
    pub fn hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let t0 = (self.min - ray.origin) * ray.inv_direction;
        let t1 = (self.max - ray.origin) * ray.inv_direction;
        let near = t0.min(t1).max_element().max(t_min);
        let far = t0.max(t1).min_element().min(t_max);
        (near <= far).then_some(near)
    }
}

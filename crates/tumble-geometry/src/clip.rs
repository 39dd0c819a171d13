//! Sutherland-Hodgman clipping of a convex polygon against a plane (the thesis's Algorithm 7),
//! in fixed-capacity arrays, carrying per-vertex feature labels through the clip.
//!
//! Every polygon edge carries a label: the feature it lies on (an edge of the incident face, or a
//! clipping plane). A vertex stores the labels of the edge arriving at it (`edge_in`) and of the
//! edge leaving it (`edge_out`); the pair names the vertex by the two features that cross there,
//! so it stays the same while the same features touch, whatever the exact positions are.
//!
//! - a vertex kept by a clip keeps both labels;
//! - where an edge labelled `L` leaves the kept half-space, the new vertex is `(L, plane)`;
//! - where an edge labelled `L` re-enters it, the new vertex is `(plane, L)`.

use crate::{Plane, Point3, Real};

/// The most vertices a clipped polygon holds: a convex quadrilateral clipped by four planes
/// gains at most one vertex per plane, so 4 + 4.
pub const MAX_CLIP_VERTICES: usize = 8;

/// A polygon vertex with the labels of the edges meeting at it.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ClipVertex {
    /// Position of the vertex.
    pub position: Point3,
    /// Label of the polygon edge arriving at this vertex.
    pub edge_in: u32,
    /// Label of the polygon edge leaving this vertex.
    pub edge_out: u32,
}

/// A convex polygon of at most [`MAX_CLIP_VERTICES`] vertices, stored inline (no heap).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ClipPolygon {
    vertices: [ClipVertex; MAX_CLIP_VERTICES],
    len: usize,
}

impl ClipPolygon {
    /// An empty polygon.
    pub fn new() -> Self {
        Self::default()
    }

    /// A polygon from its corners in order; edge `k` runs from corner `k` to corner `k + 1` and is
    /// labelled `edge_labels[k]`. Corners past [`MAX_CLIP_VERTICES`] are dropped.
    pub fn from_corners(corners: &[Point3], edge_labels: &[u32]) -> Self {
        let n = corners.len().min(edge_labels.len()).min(MAX_CLIP_VERTICES);
        let mut polygon = Self::new();
        for k in 0..n {
            polygon.push(ClipVertex {
                position: corners[k],
                edge_in: edge_labels[(k + n - 1) % n],
                edge_out: edge_labels[k],
            });
        }
        polygon
    }

    /// Appends a vertex; returns false (and drops it) when the polygon is full.
    pub fn push(&mut self, vertex: ClipVertex) -> bool {
        if self.len < MAX_CLIP_VERTICES {
            self.vertices[self.len] = vertex;
            self.len += 1;
            true
        } else {
            false
        }
    }

    /// The vertices, in order.
    pub fn vertices(&self) -> &[ClipVertex] {
        &self.vertices[..self.len]
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when no vertex is left.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The part of the polygon on the non-positive side of `plane` (signed distance <= 0), with
    /// the vertices created on the plane labelled by `plane_label` as described in the module docs.
    ///
    /// A convex input gains at most one vertex. A vertex that would overflow the capacity (only
    /// possible for a non-convex input) is dropped rather than written out of bounds.
    pub fn clip(&self, plane: &Plane, plane_label: u32) -> ClipPolygon {
        let mut out = ClipPolygon::new();
        let n = self.len;
        if n == 0 {
            return out;
        }
        let mut prev = self.vertices[n - 1];
        let mut prev_dist = plane.signed_distance(&prev.position);
        for k in 0..n {
            let cur = self.vertices[k];
            let cur_dist = plane.signed_distance(&cur.position);
            let prev_inside = prev_dist <= 0.0;
            let cur_inside = cur_dist <= 0.0;
            if prev_inside != cur_inside {
                // The signs differ, so the denominator is non-zero and t lies in [0, 1].
                let t: Real = prev_dist / (prev_dist - cur_dist);
                let position = prev.position + (cur.position - prev.position) * t;
                let (edge_in, edge_out) = if prev_inside {
                    (prev.edge_out, plane_label)
                } else {
                    (plane_label, prev.edge_out)
                };
                out.push(ClipVertex {
                    position,
                    edge_in,
                    edge_out,
                });
            }
            if cur_inside {
                out.push(cur);
            }
            prev = cur;
            prev_dist = cur_dist;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    /// The unit square [-1, 1]^2 in the z = 0 plane, edges labelled 0..4.
    fn square() -> ClipPolygon {
        let corners = [
            Point3::new(-1.0, -1.0, 0.0),
            Point3::new(1.0, -1.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(-1.0, 1.0, 0.0),
        ];
        ClipPolygon::from_corners(&corners, &[0, 1, 2, 3])
    }

    /// Shoelace area of a polygon in the z = 0 plane.
    fn area(polygon: &ClipPolygon) -> Real {
        let v = polygon.vertices();
        (0..v.len())
            .map(|k| {
                let (p, q) = (v[k].position, v[(k + 1) % v.len()].position);
                p.x * q.y - q.x * p.y
            })
            .sum::<Real>()
            * 0.5
    }

    #[test]
    fn clipping_a_square_through_its_middle_keeps_exactly_the_half() {
        let plane = Plane::from_point_normal(&Point3::origin(), &Vec3::x());
        let half = square().clip(&plane, 7);
        // Exact arithmetic on these inputs: the half square [-1, 0] x [-1, 1] has area 2.
        assert_eq!(half.len(), 4);
        assert_eq!(area(&half), 2.0);
        assert!(half.vertices().iter().all(|v| v.position.x <= 0.0));
        // The two new vertices sit on the plane and carry the plane's label on the side where the
        // polygon runs along it.
        let on_plane: Vec<_> = half
            .vertices()
            .iter()
            .filter(|v| v.position.x == 0.0)
            .collect();
        assert_eq!(on_plane.len(), 2);
        let leaving = on_plane
            .iter()
            .find(|v| v.edge_out == 7)
            .expect("exit vertex");
        let entering = on_plane
            .iter()
            .find(|v| v.edge_in == 7)
            .expect("entry vertex");
        // Edge 0 runs along y = -1 from x = -1 to x = 1: it leaves the half-space at (0, -1).
        assert_eq!((leaving.edge_in, leaving.position.y), (0, -1.0));
        // Edge 2 runs along y = 1 from x = 1 to x = -1: it re-enters at (0, 1).
        assert_eq!((entering.edge_out, entering.position.y), (2, 1.0));
    }

    #[test]
    fn a_polygon_holds_its_capacity_and_drops_the_rest() {
        let mut polygon = ClipPolygon::new();
        assert!(polygon.is_empty());
        for k in 0..MAX_CLIP_VERTICES {
            let v = ClipVertex {
                position: Point3::new(k as Real, 0.0, 0.0),
                edge_in: k as u32,
                edge_out: k as u32 + 1,
            };
            assert!(polygon.push(v), "vertex {k} fits");
            assert!(!polygon.is_empty());
        }
        assert!(!polygon.push(ClipVertex::default()), "past the capacity");
        assert_eq!(polygon.len(), MAX_CLIP_VERTICES);
        assert_eq!(polygon.vertices()[MAX_CLIP_VERTICES - 1].edge_in, 7);
        // From corners: edge k is labelled k, so vertex k has edge_in k - 1 and edge_out k.
        let square = square();
        let labels: Vec<(u32, u32)> = square
            .vertices()
            .iter()
            .map(|v| (v.edge_in, v.edge_out))
            .collect();
        assert_eq!(labels, [(3, 0), (0, 1), (1, 2), (2, 3)]);
        // Corners past the capacity are dropped, and an empty polygon clips to empty.
        let many: Vec<Point3> = (0..12).map(|k| Point3::new(k as Real, 0.0, 0.0)).collect();
        let labels: Vec<u32> = (0..12).collect();
        assert_eq!(
            ClipPolygon::from_corners(&many, &labels).len(),
            MAX_CLIP_VERTICES
        );
        let plane = Plane::from_point_normal(&Point3::origin(), &Vec3::x());
        assert!(ClipPolygon::new().clip(&plane, 0).is_empty());
    }

    #[test]
    fn kept_vertices_keep_their_labels_and_a_plane_missing_the_polygon_changes_nothing() {
        let far = Plane::from_point_normal(&Point3::new(5.0, 0.0, 0.0), &Vec3::x());
        assert_eq!(square().clip(&far, 9), square());
        let beyond = Plane::from_point_normal(&Point3::new(-5.0, 0.0, 0.0), &Vec3::x());
        assert!(square().clip(&beyond, 9).is_empty());
    }

    #[test]
    fn clipping_a_corner_off_adds_one_vertex_and_the_labels_survive_a_second_clip() {
        // Cut the corner (1, 1) with the plane x + y = 1: the corner goes, two vertices appear.
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let cut = square().clip(
            &Plane::from_point_normal(&Point3::new(0.5, 0.5, 0.0), &n),
            4,
        );
        assert_eq!(cut.len(), 5);
        // Area of the square less the corner triangle of legs 1 and 1.
        assert!((area(&cut) - 3.5).abs() < 1e-6);
        // A second, vertical cut at x = 0.25 must keep the labels of vertices it does not touch.
        let cut2 = cut.clip(
            &Plane::from_point_normal(&Point3::new(0.25, 0.0, 0.0), &Vec3::x()),
            5,
        );
        let corner = cut2
            .vertices()
            .iter()
            .find(|v| v.position == Point3::new(-1.0, 1.0, 0.0))
            .expect("the corner (-1, 1) is untouched");
        assert_eq!((corner.edge_in, corner.edge_out), (2, 3));
        // The diagonal cut lies entirely in x + y <= 1, and x <= 0.25 leaves x in [-1, 0.25].
        assert!(cut2.vertices().iter().all(|v| v.position.x <= 0.25 + 1e-6));
        assert!(
            cut2.vertices()
                .iter()
                .all(|v| v.position.x + v.position.y <= 1.0 + 1e-6)
        );
    }

    #[test]
    fn four_side_planes_clip_a_rotated_square_to_the_regular_octagon() {
        // A square of half-diagonal sqrt(2) rotated 45 degrees, clipped to |x|, |y| <= 1: the
        // result is an octagon with 8 vertices, the capacity, and area 4 - 4 * (corner triangles).
        let r = Real::sqrt(2.0);
        let corners = [
            Point3::new(r, 0.0, 0.0),
            Point3::new(0.0, r, 0.0),
            Point3::new(-r, 0.0, 0.0),
            Point3::new(0.0, -r, 0.0),
        ];
        let mut polygon = ClipPolygon::from_corners(&corners, &[0, 1, 2, 3]);
        for (label, normal) in [Vec3::x(), -Vec3::x(), Vec3::y(), -Vec3::y()]
            .iter()
            .enumerate()
        {
            let plane = Plane {
                normal: *normal,
                offset: 1.0,
            };
            polygon = polygon.clip(&plane, 4 + label as u32);
        }
        assert_eq!(polygon.len(), MAX_CLIP_VERTICES);
        // Rotated square area 4, minus four corner triangles with legs (r - 1): 4 - 4 (r-1)^2.
        let expected = 4.0 - 4.0 * (r - 1.0) * (r - 1.0);
        assert!((area(&polygon) - expected).abs() < 1e-5);
        // Every vertex is an incident edge crossing a side plane: one label of each kind.
        assert!(
            polygon
                .vertices()
                .iter()
                .all(|v| (v.edge_in < 4) != (v.edge_out < 4))
        );
    }
}

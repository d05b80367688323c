//! Exact point queries on convex hulls (parry's `ConvexPolyhedron`, the shape of
//! `ColliderBuilder::convex_hull` and of the scene files' ellipsoids and convex meshes).
//!
//! parry answers "is this point inside a hull?" by GJK, which misjudged points within half a
//! millimetre of a sharp stone's rim both ways: of the carriers it called inside after each
//! step, half were outside every face, and carriers pushed out along its projection were
//! still inside after the penetration correction's eight rounds. A hull is the intersection
//! of its faces' half-spaces, so the faces decide exactly.

use crate::math::Vector;
use rapier3d::parry::shape::ConvexPolyhedron;

/// Whether the local point `p` lies inside the hull `poly` (strictly behind every face), and
/// if so the nearest point of its surface: the foot on the nearest face's plane, which for a
/// point inside lies on the hull (it stays behind every other face).
pub(crate) fn inside(poly: &ConvexPolyhedron, p: Vector) -> Option<Vector> {
    let (pts, adj) = (poly.points(), poly.vertices_adj_to_face());
    let mut best = (f32::NEG_INFINITY, Vector::ZERO);
    for f in poly.faces() {
        let p0 = pts[adj[f.first_vertex_or_edge as usize] as usize];
        let d = f.normal.dot(p - p0);
        if d >= 0.0 {
            return None;
        }
        if d > best.0 {
            best = (d, f.normal);
        }
    }
    Some(p - best.1 * best.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stone of He 2012 Fig. 14 as the scene files build it: a hull of an ellipsoid's
    /// 12 × 9 points, flat (0.1 × 0.04 × 0.06 m) with a sharp rim.
    fn stone() -> ConvexPolyhedron {
        let mut pts = Vec::new();
        for i in 0..12 {
            for j in 0..=8 {
                let (th, ph) = (
                    i as f32 * std::f32::consts::TAU / 12.0,
                    j as f32 * std::f32::consts::PI / 8.0,
                );
                pts.push(Vector::new(
                    0.1 * ph.sin() * th.cos(),
                    0.04 * ph.cos(),
                    0.06 * ph.sin() * th.sin(),
                ));
            }
        }
        ConvexPolyhedron::from_convex_hull(&pts).unwrap()
    }

    /// Points 0.2 mm in front of and behind the middle of every face are judged by the side
    /// they lie on, and a point behind a face finds the surface within those 0.2 mm.
    #[test]
    fn points_a_hair_off_each_face_are_judged_by_their_side() {
        let poly = stone();
        let (pts, adj) = (poly.points(), poly.vertices_adj_to_face());
        for f in poly.faces() {
            let k = f.first_vertex_or_edge as usize
                ..(f.first_vertex_or_edge + f.num_vertices_or_edges) as usize;
            let centre = adj[k.clone()]
                .iter()
                .fold(Vector::ZERO, |a, &v| a + pts[v as usize])
                / k.len() as f32;
            assert!(
                inside(&poly, centre + f.normal * 2e-4).is_none(),
                "in front of a face"
            );
            let behind = centre - f.normal * 2e-4;
            let foot = inside(&poly, behind).expect("behind a face");
            assert!(
                (foot - behind).length() <= 2.0001e-4,
                "surface {foot:?} from {behind:?}"
            );
        }
    }
}

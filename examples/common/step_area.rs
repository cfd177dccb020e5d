//! The exact integral of a step over the unit square, shared by the
//! tracer's blue-noise measure, the nets' tile generator and its test.

/// The area of `{a·x + b·y < c}` inside the unit square (the square
/// clipped by the half-plane, then the shoelace formula).
pub(crate) fn step_area([a, b, c]: [f64; 3]) -> f64 {
    let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let side = |p: [f64; 2]| c - a * p[0] - b * p[1];
    let mut poly: Vec<[f64; 2]> = Vec::new();
    for i in 0..4 {
        let (p, q) = (square[i], square[(i + 1) % 4]);
        let (sp, sq) = (side(p), side(q));
        if sp > 0.0 {
            poly.push(p);
        }
        if (sp > 0.0) != (sq > 0.0) {
            let t = sp / (sp - sq);
            poly.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    let twice: f64 = (0..poly.len())
        .map(|i| {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    0.5 * twice.abs()
}

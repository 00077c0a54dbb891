// lagrangian.model.rigid_body.check_inertia on the numbers of the page: a value given to a
// parameter (a slider, a typed value, a share link) that leaves a 3-D body with an inertia
// no body has is refused with the command line's message, word for word.

const INERTIA_TOLERANCE = 1e-12; // rigid_body.PHYSICAL_TOLERANCE

// `entry`: one of page_bodies.inertia_entries; `row`: the body's row of the scene's J, [mass,
// nine entries of the tensor]; `g`: Python's format(x, "g").  The message, or null.
function inertiaProblem(entry, row, g) {
  const tensor = row.slice(1, 10);
  const numbers = entry.diagonal ? [tensor[0], tensor[4], tensor[8]] : tensor;
  // rigid_body._numbers: NaN is what the page computes where Python finds no real number
  // (a square root of a negative value) and judges nothing
  if (numbers.some(Number.isNaN)) return null;
  const infinite = numbers.findIndex((x) => !Number.isFinite(x));
  if (infinite >= 0) {
    const shown = numbers[infinite] > 0 ? "inf" : "-inf";
    return `the inertia ${entry.expressions[infinite]} = ${shown} at the parameters' values is not a finite number`;
  }
  let moments = numbers;
  if (entry.diagonal) {
    const lowest = numbers.indexOf(Math.min(...numbers));
    if (numbers[lowest] < 0) return `principal moment ${lowest + 1} is negative (${entry.expressions[lowest]} = ${g(numbers[lowest])})`;
  } else {
    moments = inertiaEigenvalues(tensor);
    const scale = Math.max(Math.max(...moments.map(Math.abs)), 1e-300);
    if (moments[0] < -INERTIA_TOLERANCE * scale) return `the tensor has a negative principal moment (${g(moments[0])})`;
    moments = moments.map((x) => Math.max(x, 0));
  }
  const total = moments.reduce((sum, x) => sum + x, 0);
  for (let k = 0; k < 3; k++) {
    if (moments[k] > total - moments[k] + INERTIA_TOLERANCE * Math.max(total, 1)) {
      return `the principal moments ${moments.map(g).join(", ")} violate the triangle inequality (I${k + 1} > the sum of the other two): no body has them`;
    }
  }
  return null;
}

// the eigenvalues of a symmetric 3 x 3 matrix (row-major, the mean of it and its transpose),
// ascending as numpy's eigvalsh gives them: Jacobi rotations
function inertiaEigenvalues(flat) {
  const a = [0, 1, 2].map((i) => [0, 1, 2].map((j) => (flat[3 * i + j] + flat[3 * j + i]) / 2));
  for (let sweep = 0; sweep < 50; sweep++) {
    const off = Math.abs(a[0][1]) + Math.abs(a[0][2]) + Math.abs(a[1][2]);
    if (off === 0 || off < 1e-300) break;
    for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
      if (a[p][q] === 0) continue;
      const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
      const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      const c = 1 / Math.sqrt(t * t + 1);
      const s = t * c;
      for (let k = 0; k < 3; k++) { // columns p and q, then rows p and q
        const [x, y] = [a[k][p], a[k][q]];
        a[k][p] = c * x - s * y;
        a[k][q] = s * x + c * y;
      }
      for (let k = 0; k < 3; k++) {
        const [x, y] = [a[p][k], a[q][k]];
        a[p][k] = c * x - s * y;
        a[q][k] = s * x + c * y;
      }
    }
  }
  return [a[0][0], a[1][1], a[2][2]].sort((x, y) => x - y);
}

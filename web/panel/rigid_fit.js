// The rigid motion that best carries one set of points onto another (least
// squares, Horn's closed form with unit quaternions: B. K. P. Horn, "Closed-
// form solution of absolute orientation using unit quaternions", JOSA A 4(4),
// 1987): here the tracker's frame onto {B}, fitted to pairs of the tracker's
// point A and the model's, as a laser tracker's software registers its frame
// to a machine's. Where the model's points do not span a plane (a platform
// standing still, or moving along a line) the rotation is not determined:
// the fit keeps the last rotation that was, or none, and only translates.
"use strict";

const rigidFit = (() => {
  // Eigen-decomposition of a symmetric matrix (Jacobi rotations): its
  // eigenvalues and eigenvectors (columns of `vectors`), unsorted.
  function symmetricEigen(matrix) {
    const n = matrix.length;
    const a = matrix.map((row) => row.slice());
    const v = a.map((_, i) => a.map((__, j) => (i === j ? 1 : 0)));
    for (let sweep = 0; sweep < 50; ++sweep) {
      let off = 0;
      for (let p = 0; p < n; ++p) for (let q = p + 1; q < n; ++q) off += a[p][q] * a[p][q];
      if (off < 1e-30) break;
      for (let p = 0; p < n; ++p) {
        for (let q = p + 1; q < n; ++q) {
          if (Math.abs(a[p][q]) < 1e-300) continue;
          const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
          const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
          const c = 1 / Math.sqrt(t * t + 1), s = t * c;
          for (let k = 0; k < n; ++k) {  // A ← A·J, then Jᵀ·A
            const akp = a[k][p], akq = a[k][q];
            a[k][p] = c * akp - s * akq;
            a[k][q] = s * akp + c * akq;
          }
          for (let k = 0; k < n; ++k) {
            const apk = a[p][k], aqk = a[q][k];
            a[p][k] = c * apk - s * aqk;
            a[q][k] = s * apk + c * aqk;
          }
          for (let k = 0; k < n; ++k) {
            const vkp = v[k][p], vkq = v[k][q];
            v[k][p] = c * vkp - s * vkq;
            v[k][q] = s * vkp + c * vkq;
          }
        }
      }
    }
    return { values: a.map((row, i) => row[i]), vectors: v };
  }

  function centroid(points) {
    const c = [0, 0, 0];
    for (const p of points) for (let k = 0; k < 3; ++k) c[k] += p[k] / points.length;
    return c;
  }

  function rotationOfQuaternion([w, x, y, z]) {
    return [[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]];
  }

  function apply(r, p) { return [0, 1, 2].map((i) => r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]); }

  // The second largest spread (m²) of `points` about their centroid: zero on a line.
  function planarSpread(points, c) {
    const m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (const p of points) {
      for (let i = 0; i < 3; ++i) for (let j = 0; j < 3; ++j) m[i][j] += (p[i] - c[i]) * (p[j] - c[j]) / points.length;
    }
    return symmetricEigen(m).values.sort((x, y) => y - x)[1];
  }

  // The rotation R minimising Σ |R·(from − c_from) − (to − c_to)|² (Horn).
  function rotation(from, to, cf, ct) {
    const s = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    from.forEach((p, n) => {
      for (let i = 0; i < 3; ++i) for (let j = 0; j < 3; ++j) s[i][j] += (p[i] - cf[i]) * (to[n][j] - ct[j]);
    });
    const [[xx, xy, xz], [yx, yy, yz], [zx, zy, zz]] = s;
    const n = [[xx + yy + zz, yz - zy, zx - xz, xy - yx],
               [yz - zy, xx - yy - zz, xy + yx, zx + xz],
               [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
               [xy - yx, zx + xz, yz + zy, -xx - yy + zz]];
    const { values, vectors } = symmetricEigen(n);
    const best = values.indexOf(Math.max(...values));
    return rotationOfQuaternion(vectors.map((row) => row[best]));
  }

  return {
    symmetricEigen,
    rotationOfQuaternion,
    // Fits `to ≈ R·from + t` over paired points; `minSpreadM2`: the
    // model's points' second spread needed to trust a rotation.
    // Returns {rotation, translation, rotated: whether R was fitted}.
    fit(from, to, minSpreadM2, fallbackRotation = null) {
      const cf = centroid(from), ct = centroid(to);
      const rotated = to.length >= 3 && planarSpread(to, ct) >= minSpreadM2;
      const r = rotated ? rotation(from, to, cf, ct) : (fallbackRotation || [[1, 0, 0], [0, 1, 0], [0, 0, 1]]);
      const rc = apply(r, cf);
      return { rotation: r, translation: [0, 1, 2].map((k) => ct[k] - rc[k]), rotated };
    },
    apply(fit, p) {
      const q = apply(fit.rotation, p);
      return [0, 1, 2].map((k) => q[k] + fit.translation[k]);
    },
  };
})();

#include "object_server/silhouette_fit.h"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "common/geometry/triangulation.h"
#include "object_server/silhouette_fit_steps.h"

namespace igms::object {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Signed distance from p to the line through a and b, and its gradient with respect to them.
double LineDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p,
                    Eigen::Vector2d* d_a, Eigen::Vector2d* d_b) {
  const Eigen::Vector2d e = b - a, q = p - a;
  const double len = std::max(e.norm(), 1e-9);
  const double c = q.x() * e.y() - q.y() * e.x();
  if (d_a) {
    const Eigen::Vector2d dc_a(-e.y() + q.y(), e.x() - q.x()), dc_b(-q.y(), q.x());
    const Eigen::Vector2d dlen_b = e / len;
    *d_a = dc_a / len + c / (len * len) * dlen_b;
    *d_b = dc_b / len - c / (len * len) * dlen_b;
  }
  return c / len;
}

// Where a point is closest to the hull: on segment `seg` (hull position), at its start or end
// vertex or in between.
struct Closest {
  double distance2 = std::numeric_limits<double>::infinity();  // squared, unsigned
  int seg = 0;
  double t = 0;  // 0 start vertex, 1 end vertex
};

Closest ToSegment(const ViewOutline& o, int seg, const Eigen::Vector2d& p) {
  const int n = static_cast<int>(o.hull.size());
  const Eigen::Vector2d& a = o.px[o.hull[seg]];
  const Eigen::Vector2d& b = o.px[o.hull[seg + 1 < n ? seg + 1 : 0]];
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  Closest c;
  c.seg = seg;
  c.t = len2 < 1e-18 ? 0.0 : std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
  c.distance2 = (a + c.t * d - p).squaredNorm();
  return c;
}

// The closest hull segment, walking from the hint's segment while the distance falls (the
// distance to a convex outline has one minimum along it for points near the outline); a
// full search when the hint's point has left the hull.
Closest FindClosest(const ViewOutline& o, int hint, const Eigen::Vector2d& p) {
  const int n = static_cast<int>(o.hull.size());
  const int start = hint >= 0 && hint < static_cast<int>(o.position.size()) ? o.position[hint] : -1;
  if (start < 0) {
    Closest best;
    for (int s = 0; s < n; ++s) {
      const Closest c = ToSegment(o, s, p);
      if (c.distance2 < best.distance2) best = c;
    }
    return best;
  }
  Closest best = ToSegment(o, start, p);
  // Outside the hull and level with the segment: the hull lies wholly on the segment's inner
  // side, so the foot of the perpendicular is the closest point of all (the common case).
  if (best.t > 0 && best.t < 1) {
    const Eigen::Vector2d& a = o.px[o.hull[start]];
    const Eigen::Vector2d e = o.px[o.hull[(start + 1) % n]] - a;
    if ((p - a).x() * e.y() - (p - a).y() * e.x() > 0) return best;
  }
  for (const int dir : {1, -1}) {
    int s = start;
    for (int steps = 0; steps < n; ++steps) {
      s += dir;
      if (s == n) s = 0;
      if (s < 0) s = n - 1;
      const Closest c = ToSegment(o, s, p);
      if (c.distance2 > best.distance2 + 1e-18) break;
      best = c;
    }
  }
  return best;
}

// Signed distance (positive outside) from the closest segment, and its gradient with respect
// to the segment's two end points.
double SignedFromClosest(const ViewOutline& o, const Closest& c, const Eigen::Vector2d& p,
                         Eigen::Vector2d* d_a, Eigen::Vector2d* d_b) {
  const int n = static_cast<int>(o.hull.size());
  const Eigen::Vector2d& a = o.px[o.hull[c.seg]];
  const Eigen::Vector2d& b = o.px[o.hull[(c.seg + 1) % n]];
  const Eigen::Vector2d e = b - a;
  const double len = e.norm();
  if (c.t > 0 && c.t < 1 && len > 1e-9) {
    const Eigen::Vector2d q = p - a;
    const Eigen::Vector2d normal(e.y() / len, -e.x() / len);  // outward, counter-clockwise hull
    const double d = normal.dot(q);
    if (d_a) {
      const Eigen::Vector2d d_e = (Eigen::Vector2d(-q.y(), q.x()) - d * e / len) / len;
      *d_b = d_e;
      *d_a = -normal - d_e;
    }
    return d;
  }
  // Nearest to a vertex: outside a convex outline.
  const Eigen::Vector2d& v = c.t <= 0 ? a : b;
  const double d = (p - v).norm();
  if (d_a) {
    const Eigen::Vector2d g = d > 1e-12 ? Eigen::Vector2d((v - p) / d) : Eigen::Vector2d::Zero();
    *d_a = c.t <= 0 ? g : Eigen::Vector2d::Zero();
    *d_b = c.t <= 0 ? Eigen::Vector2d::Zero() : g;
  }
  return d;
}

using PixelJacobian = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kMaxFitParams>;

// How far p lies beyond a convex counter-clockwise polygon (0 inside), and the gradient of
// that distance with respect to p: away from the polygon's nearest point.
double RegionExcess(const std::vector<Eigen::Vector2d>& region, const Eigen::Vector2d& p,
                    Eigen::Vector2d* grad) {
  *grad = Eigen::Vector2d::Zero();
  // Inside every side's line: inside (most points, so this is tried first).
  bool inside = true;
  for (size_t i = 0; i < region.size() && inside; ++i) {
    const Eigen::Vector2d& a = region[i];
    const Eigen::Vector2d d = region[(i + 1) % region.size()] - a;
    inside = (p - a).x() * d.y() - (p - a).y() * d.x() <= 0;
  }
  if (inside) return 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < region.size(); ++i) {
    const Eigen::Vector2d& a = region[i];
    const Eigen::Vector2d d = region[(i + 1) % region.size()] - a;
    const double len2 = d.squaredNorm();
    const double t = len2 < 1e-18 ? 0.0 : std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
    const Eigen::Vector2d off = p - (a + t * d);
    if (off.norm() < best) {
      best = off.norm();
      if (best > 1e-12) *grad = off / best;
    }
  }
  return best;
}

}  // namespace

bool ProjectOutline(const std::vector<Eigen::Vector3d>& pts, const geometry::ProjectiveCamera& cam,
                    ViewOutline& out) {
  out.px.resize(pts.size());
  const geometry::Matrix34& P = cam.P();
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d x = P * pts[i].homogeneous();
    if (cam.Depth(pts[i]) <= 0 || std::abs(x.z()) < 1e-12) return false;
    out.px[i] = x.hnormalized();
  }
  // Monotone chain on indices.
  std::vector<int> order(pts.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  const auto& p = out.px;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y());
  });
  std::vector<int> h(2 * order.size() + 1);
  size_t k = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    while (k >= 2 && Cross(p[h[k - 2]], p[h[k - 1]], p[order[i]]) <= 0) --k;
    h[k++] = order[i];
  }
  for (size_t i = order.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && Cross(p[h[k - 2]], p[h[k - 1]], p[order[i - 1]]) <= 0) --k;
    h[k++] = order[i - 1];
  }
  h.resize(k > 0 ? k - 1 : 0);
  out.hull = std::move(h);
  out.position.assign(pts.size(), -1);
  for (size_t i = 0; i < out.hull.size(); ++i) out.position[out.hull[i]] = static_cast<int>(i);
  return out.hull.size() >= 3;
}

OutlineSamples SampleOutline(const ViewOutline& o) {
  OutlineSamples out;
  const size_t n = o.hull.size();
  if (n < 3) return out;
  auto at = [&](size_t i) -> const Eigen::Vector2d& { return o.px[o.hull[i % n]]; };
  std::vector<bool> corner(n);
  std::vector<double> kappa(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d in = at(i) - at(i + n - 1), out = at(i + 1) - at(i);
    const Eigen::Vector2d a = in.normalized(), b = out.normalized();
    corner[i] = a.dot(b) < std::cos(30.0 * M_PI / 180.0);
    const double turn = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    kappa[i] = std::abs(turn) / std::max(1e-9, 0.5 * (in.norm() + out.norm()));
  }
  const double keep_off = 1.5, spacing = 1.0;
  double carry = 0;  // arc length into the next edge where the next sample falls
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = at(i);
    const Eigen::Vector2d& b = at(i + 1);
    const double len = (b - a).norm();
    if (len < 1e-9) continue;
    const Eigen::Vector2d dir = (b - a) / len;
    const Eigen::Vector2d normal(dir.y(), -dir.x());  // outward for a counter-clockwise hull
    double s = carry;
    for (; s < len; s += spacing) {
      if (corner[i] && s < keep_off) continue;
      if (corner[(i + 1) % n] && len - s < keep_off) continue;
      out.points.push_back(a + s * dir);
      out.normals.push_back(normal);
      out.segment.push_back(o.hull[i]);
      out.curvature.push_back(kappa[i] + (kappa[(i + 1) % n] - kappa[i]) * (s / len));
    }
    carry = s - len;
  }
  return out;
}

double SearchRange(int outer, double search_px) {
  return outer == 0   ? search_px
         : outer == 1 ? std::max(2.0, 0.6 * search_px)
                      : std::max(1.5, 0.4 * search_px);
}

// How far along the normal from p (at most `range`) the search may go and stay inside the
// region; below -range when even the innermost point is outside. The region is convex: the
// line p + t n leaves it where it first crosses one of its sides' lines outward.
static double OuterLimit(const std::vector<Eigen::Vector2d>& region, const Eigen::Vector2d& p,
                         const Eigen::Vector2d& n, double range) {
  if (region.empty()) return range;
  double hi = range, lo = -range;
  for (size_t i = 0; i < region.size(); ++i) {
    const Eigen::Vector2d& a = region[i];
    const Eigen::Vector2d d = region[(i + 1) % region.size()] - a;
    if (d.squaredNorm() < 1e-18) continue;
    const Eigen::Vector2d out(d.y(), -d.x());  // outward for a counter-clockwise polygon
    const double along = out.dot(n), at = out.dot(a - p);  // inside while t * along <= at
    if (along > 1e-12)
      hi = std::min(hi, at / along);
    else if (along < -1e-12)
      lo = std::max(lo, at / along);
    else if (at < 0)
      return -range - 1;  // parallel to the side and outside it
  }
  return hi >= lo ? hi : -range - 1;
}

bool InsideAny(const std::vector<std::vector<Eigen::Vector2d>>& polygons,
               const Eigen::Vector2d& p) {
  for (const auto& polygon : polygons)
    if (polygon.size() >= 3 && SignedDistance(polygon, p) < 0) return true;
  return false;
}

std::vector<Measurement> MeasureSilhouetteEdges(const ViewOutline& outline, int view,
                                                const FitView& fv, double range,
                                                const FitOptions& options, int* sampled) {
  const OutlineSamples samples = SampleOutline(outline);
  *sampled = static_cast<int>(samples.points.size());
  std::vector<Measurement> ms;
  for (size_t i = 0; i < samples.points.size(); ++i) {
    if (InsideAny(fv.hidden, samples.points[i])) {
      --*sampled;
      continue;
    }
    // The search from -range to the region's border (EdgeAlongNormal searches either side
    // of a centre): shifted by `mid`, half as wide as what is left.
    const double limit = OuterLimit(fv.region, samples.points[i], samples.normals[i], range);
    if (limit < 1 - range) continue;
    const double mid = 0.5 * (limit - range), half = 0.5 * (limit + range);
    double s;
    if (!EdgeAlongNormal(*fv.gradients, samples.points[i] + mid * samples.normals[i],
                         samples.normals[i], half, options.min_gradient, &s))
      continue;
    s += mid;
    // An edge running across the outline (a pipe's limb over a block's top) is not its edge.
    if (options.max_edge_angle_deg < 90) {
      const Eigen::Vector2d g = fv.gradients->At(samples.points[i] + s * samples.normals[i]);
      if (std::abs(g.dot(samples.normals[i])) <
          std::cos(options.max_edge_angle_deg * M_PI / 180) * g.norm())
        continue;
    }
    if (fv.limb_shift_px != 0) {  // a pipe's limb, read inside it for its side's shading
      const int n = static_cast<int>(outline.px.size()), a = samples.segment[i];
      const int at = outline.position[a];
      const int b = at >= 0 ? outline.hull[(at + 1) % outline.hull.size()] : a;
      if ((a < n / 2) != (b < n / 2)) s += fv.limb_shift_px;
    }
    if (const size_t a = static_cast<size_t>(samples.segment[i]); a < fv.segment_shift_px.size())
      s += fv.segment_shift_px[a];
    // Where the outline turns fast (a thin pipe's ends) the blur moves the edge most.
    const double k =
        std::min(samples.curvature[i], 1.0 / std::max(1e-9, 1.5 * options.edge_blur_px));
    s += 0.5 * options.edge_blur_px * options.edge_blur_px * k;
    if (InsideAny(fv.hidden, samples.points[i] + s * samples.normals[i])) continue;
    ms.push_back({view, samples.points[i] + s * samples.normals[i], samples.segment[i]});
  }
  return ms;
}

std::vector<Measurement> MeasureSilhouetteEdges(const ViewOutline& outline, int view,
                                                const Gradients& gradients, double range,
                                                const FitOptions& options, int* sampled) {
  return MeasureSilhouetteEdges(outline, view, FitView(nullptr, &gradients), range, options,
                                sampled);
}

void MeasureInnerEdges(const std::vector<InnerEdge>& edges, const ViewOutline& o, int view,
                       const FitView& fv, double range, double min_gradient,
                       std::vector<Measurement>& ms) {
  for (const InnerEdge& e : edges) {
    if (e.chain.size() < 2) continue;
    const Eigen::Vector2d first = o.px[e.chain.front()], last = o.px[e.chain.back()];
    double total = 0;
    for (size_t i = 0; i + 1 < e.chain.size(); ++i)
      total += (o.px[e.chain[i + 1]] - o.px[e.chain[i]]).norm();
    if (total < 10 || (last - first).norm() < 1e-9) continue;
    const Eigen::Vector2d span = (last - first).normalized(), across(span.y(), -span.x());
    const double width = std::min(std::abs(across.dot(o.px[e.c1] - first)),
                                  std::abs(across.dot(o.px[e.c2] - first)));
    if (width < e.min_width_px) continue;
    const double reach = std::min(range, 0.4 * width);
    double walked = 0, next = 3;
    for (size_t i = 0; i + 1 < e.chain.size(); ++i) {
      const Eigen::Vector2d a = o.px[e.chain[i]], b = o.px[e.chain[i + 1]];
      const double len = (b - a).norm();
      if (len < 1e-9) continue;
      const Eigen::Vector2d dir = (b - a) / len, normal(dir.y(), -dir.x());
      for (; next < walked + len && next <= total - 3; next += 1.0) {
        const Eigen::Vector2d p = a + (next - walked) * dir;
        double s;
        if (!InsideAny(fv.hidden, p) &&
            EdgeNearPoint(*fv.gradients, p, normal, reach, min_gradient, &s))
          ms.push_back({view, p + s * normal, 0, e.chain[i], e.chain[i + 1]});
      }
      walked += len;
    }
  }
}

double RobustCost(double residual, double huber, double outlier) {
  const double a = std::min(std::abs(residual), outlier), k = huber;
  return a <= k ? 0.5 * a * a : k * (a - 0.5 * k);
}

double RobustWeight(double residual, double huber, double outlier) {
  const double a = std::abs(residual);
  return a > outlier ? 0.0 : (a <= huber ? 1.0 : huber / a);
}

bool OutlineResiduals::Outlines(const Eigen::VectorXd& x, std::array<ViewOutline, 2>& o) const {
  pts_ = outline_(x);
  for (int v = 0; v < 2; ++v)
    if (!ProjectOutline(pts_, *views_[v].camera, o[v])) return false;
  return true;
}

bool OutlineResiduals::Residuals(const Eigen::VectorXd& x, std::vector<Measurement>& ms,
                                 Eigen::VectorXd& r, Eigen::MatrixXd* J) const {
  std::array<ViewOutline, 2> o;
  if (!Outlines(x, o)) return false;
  const int np = static_cast<int>(x.size());
  // The outline points beyond their view's region, and which way that distance grows.
  std::array<std::vector<double>, 2> excess;
  std::array<std::vector<Eigen::Vector2d>, 2> excess_grad;
  Eigen::Index region_rows = 0;
  if (region_weight_ > 0)
    for (int v = 0; v < 2; ++v) {
      if (views_[v].region.empty()) continue;
      // Only the hull's points can lie beyond a convex region the hull does not leave.
      excess[v].assign(pts_.size(), 0.0);
      excess_grad[v].assign(pts_.size(), Eigen::Vector2d::Zero());
      for (const int i : o[v].hull)
        excess[v][i] = RegionExcess(views_[v].region, o[v].px[i], &excess_grad[v][i]);
      region_rows += static_cast<Eigen::Index>(pts_.size());
    }
  // d(pixel)/d(params) of the outline points a residual depends on in each view: the
  // hull's, the measured inner edges' and those beyond the region (a cylinder's far cap
  // points are often none of these).
  std::array<std::vector<PixelJacobian>, 2> dpx;
  if (J) {
    std::array<std::vector<bool>, 2> needed;
    for (int v = 0; v < 2; ++v) {
      needed[v].assign(pts_.size(), false);
      for (const int i : o[v].hull) needed[v][i] = true;
      for (size_t i = 0; i < excess[v].size(); ++i)
        if (excess[v][i] > 0) needed[v][i] = true;
    }
    for (const Measurement& m : ms)
      if (m.a >= 0) needed[m.view][m.a] = needed[m.view][m.b] = true;
    const std::vector<Eigen::Vector3d> base = pts_;
    std::vector<std::vector<Eigen::Vector3d>> moved(np);
    for (int k = 0; k < np; ++k) {
      Eigen::VectorXd xp = x;
      xp[k] += step_[k];
      moved[k] = outline_(xp);
    }
    for (int v = 0; v < 2; ++v) {
      dpx[v].resize(base.size());
      for (size_t i = 0; i < base.size(); ++i) {
        if (!needed[v][i]) continue;
        const Eigen::Matrix<double, 2, 3> jp =
            geometry::ProjectionJacobian(views_[v].camera->P(), base[i]);
        dpx[v][i].resize(2, np);
        for (int k = 0; k < np; ++k) dpx[v][i].col(k) = jp * ((moved[k][i] - base[i]) / step_[k]);
      }
    }
    J->setZero(static_cast<Eigen::Index>(ms.size()) + region_rows, np);
  }
  r.resize(static_cast<Eigen::Index>(ms.size()) + region_rows);
  for (size_t i = 0; i < ms.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    const ViewOutline& ov = o[ms[i].view];
    if (ms[i].a >= 0) {
      Eigen::Vector2d da, db;
      r[row] = LineDistance(ov.px[ms[i].a], ov.px[ms[i].b], ms[i].point, J ? &da : nullptr,
                            J ? &db : nullptr);
      if (J)
        J->row(row) =
            da.transpose() * dpx[ms[i].view][ms[i].a] + db.transpose() * dpx[ms[i].view][ms[i].b];
      continue;
    }
    const Closest c = FindClosest(ov, ms[i].hint, ms[i].point);
    const int n = static_cast<int>(ov.hull.size());
    const int ia = ov.hull[c.seg], ib = ov.hull[(c.seg + 1) % n];
    ms[i].hint = ia;
    Eigen::Vector2d da, db;
    r[row] = SignedFromClosest(ov, c, ms[i].point, J ? &da : nullptr, J ? &db : nullptr);
    if (J)
      J->row(row) = da.transpose() * dpx[ms[i].view][ia] + db.transpose() * dpx[ms[i].view][ib];
  }
  auto row = static_cast<Eigen::Index>(ms.size());
  const double scale = std::sqrt(region_weight_);
  for (int v = 0; v < 2; ++v)
    for (size_t i = 0; i < excess[v].size(); ++i, ++row) {
      r[row] = scale * excess[v][i];
      if (J && excess[v][i] > 0) J->row(row) = scale * excess_grad[v][i].transpose() * dpx[v][i];
    }
  return true;
}

void RefineParameters(const OutlineResiduals& residuals, const FitOptions& options, double outlier,
                      std::vector<Measurement>& ms, Eigen::VectorXd& x) {
  const int np = static_cast<int>(x.size());
  // Rows past the measurements are the region's (OutlineResiduals::Residuals): plain squares.
  auto cost_of = [&](const Eigen::VectorXd& res) {
    const auto measured = static_cast<Eigen::Index>(ms.size());
    double c = 0;
    for (Eigen::Index i = 0; i < res.size(); ++i)
      c += i < measured ? RobustCost(res[i], options.huber_px, outlier) : 0.5 * res[i] * res[i];
    return c;
  };
  Eigen::VectorXd r, w;
  Eigen::MatrixXd J;
  double lambda = 1e-3;
  for (int inner = 0; inner < options.inner_iterations; ++inner) {
    if (!residuals.Residuals(x, ms, r, &J)) break;
    w.resize(r.size());
    for (Eigen::Index i = 0; i < r.size(); ++i)
      w[i] = i < static_cast<Eigen::Index>(ms.size())
                 ? RobustWeight(r[i], options.huber_px, outlier)
                 : 1.0;
    const Eigen::MatrixXd JtW = J.transpose() * w.asDiagonal();
    const Eigen::MatrixXd H = JtW * J;
    const Eigen::VectorXd g = JtW * r;
    const double cost = cost_of(r);
    bool improved = false;
    double gain = 0;
    for (int tries = 0; tries < 8 && !improved; ++tries) {
      Eigen::MatrixXd A = H;
      // Directions no edge constrains (an end with no measurement yet) must not drift:
      // a small stiffness relative to the mean curvature holds them.
      A.diagonal() +=
          lambda * H.diagonal() + Eigen::VectorXd::Constant(np, 1e-6 * H.diagonal().mean() + 1e-9);
      const Eigen::VectorXd dx = -A.ldlt().solve(g);
      Eigen::VectorXd rn;
      std::vector<Measurement> trial = ms;
      if (dx.allFinite() && residuals.Residuals(x + dx, trial, rn, nullptr) && cost_of(rn) < cost) {
        gain = cost - cost_of(rn);
        x += dx;
        ms = std::move(trial);
        lambda = std::max(1e-7, lambda * 0.3);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    // Converged: a step that gains almost nothing ends this measurement's iterations.
    if (!improved || gain < 1e-4 * (1 + cost)) break;
  }
}

bool OutlineSettled(const std::array<ViewOutline, 2>& before,
                    const std::array<ViewOutline, 2>& after, double settled_px) {
  double moved = 0;
  for (int v = 0; v < 2; ++v)
    for (size_t i = 0; i < after[v].px.size(); ++i)
      moved = std::max(moved, (after[v].px[i] - before[v].px[i]).squaredNorm());
  return moved < settled_px * settled_px;
}

bool FinishFit(const OutlineResiduals& residuals, const Eigen::VectorXd& x,
               std::vector<Measurement>& ms, const FitOptions& options, FitOutcome* out) {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  if (!residuals.Residuals(x, ms, r, &J)) return false;
  const int np = static_cast<int>(x.size());
  std::array<double, 2> sum{0, 0};
  std::array<int, 2> count{0, 0};
  // The region's rows (past the measurements) say nothing of the edges: weight 0.
  Eigen::VectorXd wk = Eigen::VectorXd::Zero(r.size());
  double inner_sum = 0;
  for (int i = 0; i < static_cast<int>(ms.size()); ++i) {
    const bool in = std::abs(r[i]) <= options.outlier_px;
    out->measured[ms[i].view].push_back(ms[i].point);
    out->inlier[ms[i].view].push_back(in);
    if (!in) continue;
    wk[i] = 1;
    if (ms[i].a >= 0) {
      inner_sum += r[i] * r[i];
      ++out->inner_used[ms[i].view];
      continue;
    }
    sum[ms[i].view] += r[i] * r[i];
    ++count[ms[i].view];
  }
  for (int v = 0; v < 2; ++v) {
    out->used[v] = count[v];
    out->rms_px[v] = count[v] ? std::sqrt(sum[v] / count[v]) : 0;
  }
  const int kept = count[0] + count[1] + out->inner_used[0] + out->inner_used[1];
  const double dof = std::max(1, kept - np);
  const double sigma2 =
      std::max((sum[0] + sum[1] + inner_sum) / dof, options.min_sigma_px * options.min_sigma_px) *
      std::max(1.0, options.correlated_samples);
  const Eigen::MatrixXd H = J.transpose() * wk.asDiagonal() * J;
  // A direction no edge holds (the height of a block whose top the pipe it carries hides) must
  // come out unknown, not exact as a pseudo-inverse would have it: a prior of kUnheldSigma
  // (world units, radians for a yaw) on every parameter, far weaker than any measurement.
  constexpr double kUnheldSigma = 100.0;
  const Eigen::MatrixXd H_inv =
      (H + Eigen::MatrixXd::Identity(np, np) * (sigma2 / (kUnheldSigma * kUnheldSigma)))
          .ldlt()
          .solve(Eigen::MatrixXd::Identity(np, np));
  out->covariance = sigma2 * H_inv;
  // The parameters' move for every kept silhouette edge shifted outline_shift_px outward.
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(r.size());
  for (int i = 0; i < static_cast<int>(ms.size()); ++i)
    if (wk[i] > 0 && ms[i].a < 0) shift[i] = options.outline_shift_px;
  const Eigen::VectorXd moved = H_inv * (J.transpose() * shift);
  out->covariance += moved * moved.transpose();
  std::array<ViewOutline, 2> o;
  if (residuals.Outlines(x, o))
    for (int v = 0; v < 2; ++v)
      for (const int i : o[v].hull) out->outline[v].push_back(o[v].px[i]);
  return true;
}

std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && Cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && Cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

double SignedDistance(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  const size_t n = hull.size();
  double max_line = -std::numeric_limits<double>::infinity();
  double min_seg = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % n];
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    if (len2 < 1e-18) continue;
    const Eigen::Vector2d normal = Eigen::Vector2d(d.y(), -d.x()) / std::sqrt(len2);
    max_line = std::max(max_line, normal.dot(p - a));
    const double t = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
    min_seg = std::min(min_seg, (a + t * d - p).norm());
  }
  return max_line <= 0 ? max_line : min_seg;
}
FitOutcome FitSilhouette(const OutlineFn& outline, const Eigen::VectorXd& initial,
                         const std::array<FitView, 2>& views, const FitOptions& options,
                         const InnerEdgesFn& inner) {
  // A pass that moves no outline point farther than this has settled the fit.
  constexpr double kSettledPx = 0.01;
  FitOutcome out;
  Eigen::VectorXd x = initial;
  const int np = static_cast<int>(x.size());
  if (np < 1 || np > kMaxFitParams) {
    out.error = "a model needs 1 to " + std::to_string(kMaxFitParams) + " parameters";
    return out;
  }
  const Eigen::VectorXd step =
      options.step.size() == np ? options.step : Eigen::VectorXd::Constant(np, 1e-4);
  const OutlineResiduals residuals(outline, views, step, options.region_weight);
  const char* behind = "the model went behind a camera";
  std::vector<Measurement> ms;
  for (int outer = options.first_outer; outer < options.outer_iterations; ++outer) {
    // 1. The outline in both views.
    const double range = SearchRange(outer, options.search_px);
    std::array<ViewOutline, 2> o;
    if (!residuals.Outlines(x, o)) {
      out.error = behind;
      return out;
    }
    // 2. The edges along it (and across the inner edges).
    ms.clear();
    for (int v = 0; v < 2; ++v) {
      const std::vector<Measurement> silhouette =
          MeasureSilhouetteEdges(o[v], v, views[v], range, options, &out.sampled[v]);
      ms.insert(ms.end(), silhouette.begin(), silhouette.end());
      if (inner)
        MeasureInnerEdges(inner(x, views[v].camera->Center()), o[v], v, views[v], range,
                          options.min_gradient, ms);
    }
    if (spdlog::should_log(spdlog::level::debug)) {
      std::string params;
      for (int i = 0; i < x.size(); ++i) params += fmt::format("{:.4f} ", x[i]);
      spdlog::debug("silhouette fit, pass {}: sampled {}/{}, {} edge measurements, x = {}", outer,
                    out.sampled[0], out.sampled[1], ms.size(), params);
    }
    if (static_cast<int>(ms.size()) < 2 * np) {
      out.error = "too few edge points along the model's outline";
      return out;
    }
    // 3. The model onto them; the outlier bound grows with the search range in early passes.
    RefineParameters(residuals, options, std::max(options.outlier_px, range + 0.5), ms, x);
    // 4. Passes from the third on search the same range: once a pass has left the outline
    // where it was measured, measuring again would find the same edges.
    if (outer >= 2 && outer + 1 < options.outer_iterations) {
      std::array<ViewOutline, 2> now;
      if (residuals.Outlines(x, now) && OutlineSettled(o, now, kSettledPx)) break;
    }
  }
  // Final statistics and covariance on the last measurements.
  if (!FinishFit(residuals, x, ms, options, &out)) {
    out.error = behind;
    return out;
  }
  out.params = x;
  out.ok = x.allFinite();
  if (!out.ok) out.error = "the fit diverged";
  return out;
}

}  // namespace igms::object

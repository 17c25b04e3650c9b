// LocateOptions::Check: each option within the range the locator's steps are built for, so a
// configuration error is named before any image is looked at.
#include <cmath>
#include <string>

#include "object_server/locate.h"

namespace igms::object {

bool LocateOptions::Check(std::string* error) const {
  if (!(depth_tolerance > 0)) {
    *error = "depth_tolerance must be positive";
    return false;
  }
  for (const double share : lowered_shares)
    if (!(share > 0 && share < 1)) {
      *error = "lowered_shares must each be in (0, 1)";
      return false;
    }
  if (floor_height && !std::isfinite(*floor_height)) {
    *error = "floor_height must be a finite number when given";
    return false;
  }
  if (!(floor_gap >= 0) || !(pipe_floor_gap >= 0) || !(floor_sink >= 0) ||
      !(background_foot_ratio >= 0)) {
    *error = "floor_gap, pipe_floor_gap, floor_sink and background_foot_ratio must not be negative";
    return false;
  }
  // An upright pipe's axis rises: its foot is moved along it to the floor.
  if (!(upright_axis_cos > 0 && upright_axis_cos <= 1)) {
    *error = "upright_axis_cos must be in (0, 1]";
    return false;
  }
  if (!(edge_sigma >= 0 && edge_sigma <= 10)) {
    *error = "edge_sigma must be in 0..10";
    return false;
  }
  if (!(camera_blur_px >= 0 && camera_blur_px <= 10)) {
    *error = "camera_blur_px must be in 0..10";
    return false;
  }
  if (!(known_reach_sigmas >= 0)) {
    *error = "known_reach_sigmas must not be negative";
    return false;
  }
  if (!(max_shared_volume > 0 && max_shared_volume <= 1)) {
    *error = "max_shared_volume must be in (0, 1]";
    return false;
  }
  if (!(box_side_reach > 0 && box_side_reach <= 1) || !(max_lowered_size_sigma > 0)) {
    *error = "box_side_reach must be in (0, 1], max_lowered_size_sigma positive";
    return false;
  }
  if (!(flat_side_gain >= 0) || !(crease_gain > 0) || !(round_side_gain >= flat_side_gain) ||
      !(even_side_gain >= 0)) {
    *error =
        "flat_side_gain and even_side_gain must not be negative, crease_gain must be positive, "
        "round_side_gain at least flat_side_gain";
    return false;
  }
  if (!(faint_round_side_gain >= 0 && faint_round_side_gain <= round_side_gain) ||
      !(faint_round_box_ratio > 0 && faint_round_box_ratio <= 1)) {
    *error =
        "faint_round_side_gain must be in [0, round_side_gain], faint_round_box_ratio in (0, 1]";
    return false;
  }
  if (!(min_open_depth_sigma >= 0)) {
    *error = "min_open_depth_sigma must not be negative";
    return false;
  }
  if (!(face_crease_gain >= 0) || !(min_face_crease_step >= 0) ||
      !(face_crease_agree > 0 && face_crease_agree <= 1)) {
    *error =
        "face_crease_gain and min_face_crease_step must not be negative, face_crease_agree must "
        "be in (0, 1]";
    return false;
  }
  if (!(raised_pipe_max_tilt_deg >= 0 && raised_pipe_max_tilt_deg <= 90) ||
      !(leaning_pipe_score >= 0)) {
    *error = "raised_pipe_max_tilt_deg must be in 0..90, leaning_pipe_score not negative";
    return false;
  }
  if (!(box_clearly_over_cylinder_supported >= 0 && box_clearly_over_cylinder_supported <= 1)) {
    *error = "box_clearly_over_cylinder_supported must be in 0..1";
    return false;
  }
  if (!(box_sigma_score_floor >= 0) || !(box_sigma_score_gain >= 0)) {
    *error = "box_sigma_score_floor and box_sigma_score_gain must not be negative";
    return false;
  }
  if (!(edge_fraction > 0 && edge_fraction < 1)) {
    *error = "edge_fraction must be in (0, 1)";
    return false;
  }
  if (!(edge_strength_quantile > 0 && edge_strength_quantile <= 1) ||
      !(retry_edge_quantile >= 0 && retry_edge_quantile <= 1)) {
    *error = "edge_strength_quantile must be in (0, 1] and retry_edge_quantile in [0, 1]";
    return false;
  }
  if (!(retry_noise_gradient >= 0 && std::isfinite(retry_noise_gradient)) ||
      !(retry_min_edge_gradient > 0 && std::isfinite(retry_min_edge_gradient))) {
    *error = "retry_noise_gradient must be finite and at least 0, retry_min_edge_gradient over 0";
    return false;
  }
  if (!(search_px >= 1 && search_px <= 20)) {
    *error = "search_px must be in 1..20";
    return false;
  }
  if (outer_iterations < 1 || inner_iterations < 1) {
    *error = "iterations must be at least 1";
    return false;
  }
  if (!(region_weight >= 0) || !(cylinder_depth_reach > 0) || !(stretch_margin >= 0) ||
      !(min_radius_px >= 0) || !(max_limb_shading_px >= 0)) {
    *error =
        "region_weight, stretch_margin, min_radius_px and max_limb_shading_px must not be "
        "negative, cylinder_depth_reach must be positive";
    return false;
  }
  if (!(max_face_shading_px >= 0) || !(max_face_px > 0)) {
    *error = "max_face_shading_px must not be negative, max_face_px must be positive";
    return false;
  }
  if (!(match_band_px >= 0 && match_band_px <= 64)) {
    *error = "match_band_px must be in 0..64";
    return false;
  }
  if (!(max_shown_fit_score >= max_fit_score) || !(max_upright_supported_score >= 0) ||
      !(min_shown_side_share >= 0 && min_shown_side_share <= 1) ||
      !(max_limb_edge_difference >= 0 && max_limb_edge_difference <= 1)) {
    *error =
        "max_shown_fit_score must be at least max_fit_score, max_upright_supported_score not "
        "negative, min_shown_side_share and max_limb_edge_difference in 0..1";
    return false;
  }
  if (!(max_rms_px > 0) || !(max_fit_score > 0) || !(max_lying_fit_score >= max_fit_score) ||
      !(max_lying_supported_score >= 0) || !(score_reference_width_px > 0) ||
      !(score_width_power >= 0) || !(sigma_width_power >= 0) ||
      !(min_match_zncc > -1 && min_match_zncc < 1)) {
    *error = "thresholds must be positive (max_lying_fit_score at least max_fit_score)";
    return false;
  }
  return true;
}

}  // namespace igms::object

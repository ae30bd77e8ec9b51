#include "camopt/core/design_spec.hpp"

namespace camopt {

const char* to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::rotational: return "rotational";
    case NodeKind::translational: return "translational";
    case NodeKind::floating: return "floating";
  }
  return "?";
}

const char* to_string(ConnectionKind kind) {
  switch (kind) {
    case ConnectionKind::link: return "link";
    case ConnectionKind::crank_slider: return "crank_slider";
    case ConnectionKind::gear: return "gear";
    case ConnectionKind::variable_gear: return "variable_gear";
    case ConnectionKind::rack_pinion: return "rack_pinion";
    case ConnectionKind::contact: return "contact";
  }
  return "?";
}

const char* to_string(ProfileForm form) {
  switch (form) {
    case ProfileForm::polar: return "polar";
    case ProfileForm::xy: return "xy";
    case ProfileForm::base_plus_lift: return "base_plus_lift";
    case ProfileForm::circle: return "circle";
    case ProfileForm::eccentric: return "eccentric";
  }
  return "?";
}

const char* to_string(SurfaceShape shape) {
  switch (shape) {
    case SurfaceShape::profile: return "profile";
    case SurfaceShape::circle: return "circle";
    case SurfaceShape::line: return "line";
  }
  return "?";
}

const char* to_string(ContactLaw law) {
  switch (law) {
    case ContactLaw::hertz: return "hertz";
    case ContactLaw::linear: return "linear";
  }
  return "?";
}

const char* to_string(ContactDampingLaw law) {
  switch (law) {
    case ContactDampingLaw::hunt_crossley: return "hunt_crossley";
    case ContactDampingLaw::linear: return "linear";
  }
  return "?";
}

}  // namespace camopt

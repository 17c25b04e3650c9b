// The sound bank keys the session plays (sound_server/bank/manifest.yaml; Cooke, tables 2.5
// and 2.6). The bank is the only place a sound is defined; these are its names.
// kUnmark, kNoEcho and kServerBack are the entries issue 17 adds to the bank.
#pragma once

namespace igms::control::cues {

inline constexpr const char* kCameraClick = "camera_click";
inline constexpr const char* kRicochet = "ricochet";
inline constexpr const char* kWoodblock = "woodblock";
inline constexpr const char* kBellTree = "bell_tree";
inline constexpr const char* kIntroductionMusic = "introduction_music";
inline constexpr const char* kModelingAsBox = "modeling_as_box";
inline constexpr const char* kModelingAsCylinder = "modeling_as_cylinder";
inline constexpr const char* kFreezing = "freezing";
inline constexpr const char* kUnfreezing = "unfreezing";
inline constexpr const char* kRemovingPoints = "removing_points";
inline constexpr const char* kRemovingModel = "removing_model";
inline constexpr const char* kPleaseWait = "please_wait";
inline constexpr const char* kLocatingObject = "locating_object";
inline constexpr const char* kWelcome = "welcome";
inline constexpr const char* kBoxOrCylinder = "box_or_cylinder";
inline constexpr const char* kServerLost = "server_lost";
inline constexpr const char* kDeviceLost = "device_lost";
inline constexpr const char* kDeviceBack = "device_back";
inline constexpr const char* kUnmark = "unmark";
inline constexpr const char* kNoEcho = "no_echo";
inline constexpr const char* kServerBack = "server_back";

}  // namespace igms::control::cues

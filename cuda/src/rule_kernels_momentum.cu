// The step kernels of the motion model with the pressure and momentum levers (the side plane):
// RuleLaunch (rule_launch.cuh) instantiated for its Rule type.
#include "rule_kernels.cuh"

template struct granular::cuda::RuleLaunch<granular::MotionRule<granular::cuda::DevicePlatform, false, true, true>>;

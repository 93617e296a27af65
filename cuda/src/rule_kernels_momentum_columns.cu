// The step kernels of the motion model with the columns, pressure and momentum levers: RuleLaunch
// (rule_launch.cuh) instantiated for its Rule type.
#include "rule_kernels.cuh"

template struct granular::cuda::RuleLaunch<granular::MotionRule<granular::cuda::DevicePlatform, true, true, true>>;

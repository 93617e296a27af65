// The step kernels of the one-step rules: RuleLaunch (rule_launch.cuh) instantiated for its Rule
// type.
#include "rule_kernels.cuh"

template struct granular::cuda::RuleLaunch<granular::OneStepRule<false, granular::cuda::DevicePlatform>>;

// The marching cubes' iso-level: a look's surface lies where the fraction of the 8 cells around a
// lattice point that have the look crosses it (mc_build.comp meshes it, section_cap.frag closes
// its cut at the section plane).
const float kIso = 0.35;

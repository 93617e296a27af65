// The cells a marching-cubes brick reads: the brick and a border of 2, cells -2..18 along each axis
// (local to the brick). mc_classify.comp looks at them to decide whether mc_build.comp, which
// loads them into shared memory, has a surface to mesh.
const int kTile = 21;

#pragma once
// Marks functions that both g++ and nvcc compile, so CPU and CUDA share one
// implementation of the physics.

#if defined(__CUDACC__)
#define GRANFLOW_HD __host__ __device__
#else
#define GRANFLOW_HD
#endif

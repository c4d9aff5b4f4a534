# lib/math (comlearn/math3d.h): vec3, quaternion, pose and PRNG against analytic values and the
# pinned streams of the copies it replaced.
comlearn_add_check(check_math SOURCES check_math.c LIBS comlearn_math TIMEOUT 60)

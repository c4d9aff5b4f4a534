comlearn_add_check(check_model
  SOURCES check_model.c model_mesh_tests.c model_massprop_tests.c model_hull_tests.c
          model_urdf_tests.c
  LIBS comlearn_model_sim)

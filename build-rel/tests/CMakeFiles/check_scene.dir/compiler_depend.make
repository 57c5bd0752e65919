# Empty compiler generated dependencies file for check_scene.
# This may be replaced when dependencies are built.

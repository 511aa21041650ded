# The texture generator (tools/make_textures.cpp). The PNGs it writes are committed under textures/;
# run `make_textures` (or `cmake --build <dir> --target textures`) to regenerate them.
add_executable(make_textures tools/make_textures.cpp)
target_include_directories(make_textures SYSTEM PRIVATE /usr/include/stb)
target_link_libraries(make_textures PRIVATE glm::glm drape_warnings)
target_compile_definitions(make_textures PRIVATE DRAPE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
add_custom_target(textures COMMAND make_textures ${CMAKE_SOURCE_DIR}/textures
                  COMMENT "Regenerating textures/ (committed PNGs)")

# The mesh generator (tools/make_meshes.cpp). The OBJ files it writes are committed under scenes/meshes/;
# run `cmake --build <dir> --target meshes` to regenerate them.
add_executable(make_meshes tools/make_meshes.cpp)
target_link_libraries(make_meshes PRIVATE glm::glm drape_warnings)
target_compile_definitions(make_meshes PRIVATE DRAPE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
add_custom_target(meshes COMMAND make_meshes ${CMAKE_SOURCE_DIR}/scenes/meshes
                  COMMENT "Regenerating scenes/meshes/ (committed OBJ files)")

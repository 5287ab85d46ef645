# A private MeshLab prefix for the tests, so nothing is written to /usr: MeshLab finds plugins
# only next to its binary (../lib/x86_64-linux-gnu/meshlab/plugins), and a symlinked binary
# resolves to /usr/bin, so the binaries are copied and everything else is linked.
# Inputs: PREFIX, PLUGIN (our .so), MESHLAB_LIB_DIR (Debian's lib/x86_64-linux-gnu/meshlab).
if(NOT EXISTS "${MESHLAB_LIB_DIR}/libmeshlab-common.so")
  message(FATAL_ERROR "make_prefix: no libmeshlab-common.so in '${MESHLAB_LIB_DIR}'")
endif()
set(lib "${PREFIX}/lib/x86_64-linux-gnu/meshlab")
file(REMOVE_RECURSE "${PREFIX}")
file(MAKE_DIRECTORY "${PREFIX}/bin" "${lib}/plugins")
file(COPY /usr/bin/meshlabserver /usr/bin/meshlab DESTINATION "${PREFIX}/bin")
file(GLOB common_libs "${MESHLAB_LIB_DIR}/libmeshlab-common.so*")
foreach(f ${common_libs})
  get_filename_component(name "${f}" NAME)
  file(CREATE_LINK "${f}" "${lib}/${name}" SYMBOLIC)
endforeach()
file(GLOB plugins "${MESHLAB_LIB_DIR}/plugins/*.so")
foreach(f ${plugins})
  get_filename_component(name "${f}" NAME)
  if(NOT name STREQUAL "libfilter_ricci_flow.so")  # an installed copy of ours is replaced
    file(CREATE_LINK "${f}" "${lib}/plugins/${name}" SYMBOLIC)
  endif()
endforeach()
file(CREATE_LINK "${PLUGIN}" "${lib}/plugins/libfilter_ricci_flow.so" SYMBOLIC)

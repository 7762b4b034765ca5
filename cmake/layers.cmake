# vs_layer(NAME SOURCES ... [BELOW layer ...] [DEPS target ...]): the object library of one folder
# of src/. Its include path is its own folder, the public include/ and, through BELOW, the
# layers under it (transitively): an #include of a higher layer's header does not compile.
# DEPS are the third-party libraries its sources call. Compiled once, position-independent and
# with hidden visibility: the shared libraries export only what VS_API marks (voussoir/api.h),
# and the tests link the same objects statically (src/CMakeLists.txt).
function(vs_layer name)
  cmake_parse_arguments(L "" "" "SOURCES;BELOW;DEPS" ${ARGN})
  add_library(${name} OBJECT ${L_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}
                             ${PROJECT_SOURCE_DIR}/include ${PROJECT_BINARY_DIR}/include)
  target_link_libraries(${name} PUBLIC ${L_BELOW} ${L_DEPS})
  target_compile_options(${name} PRIVATE ${VS_WARNINGS})
  target_compile_definitions(${name} PRIVATE VS_BUILDING_LIBRARY)
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON
                        C_VISIBILITY_PRESET hidden VS_LAYER_DEPS "${L_DEPS}")
endfunction()

# The third-party libraries that the objects of layers ... call (their DEPS, not those of the
# layers below them), into the variable out.
function(vs_layer_deps out)
  set(deps "")
  foreach(l IN LISTS ARGN)
    get_target_property(d ${l} VS_LAYER_DEPS)
    if(d)
      list(APPEND deps ${d})
    endif()
  endforeach()
  set(${out} ${deps} PARENT_SCOPE)
endfunction()

# vs_add_library(target name OBJECTS layer ...): a shared library lib<name>.so.MAJOR of those
# layers' objects, versioned from the project's version.
function(vs_add_library target name)
  cmake_parse_arguments(L "" "" "OBJECTS" ${ARGN})
  set(objs "")
  foreach(l IN LISTS L_OBJECTS)
    list(APPEND objs $<TARGET_OBJECTS:${l}>)
  endforeach()
  add_library(${target} SHARED ${objs})
  set_target_properties(${target} PROPERTIES OUTPUT_NAME ${name}
                        VERSION ${PROJECT_VERSION} SOVERSION ${VS_SOVERSION}
                        INSTALL_RPATH "$ORIGIN")
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  vs_layer_deps(deps ${L_OBJECTS}) # what these objects call, nothing more
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:${deps}>)
  # A call from the library to one of its own functions binds to it: no interposition through
  # the PLT, so the compiler may inline it and the dynamic linker has nothing to look up.
  target_link_options(${target} PRIVATE -Wl,-Bsymbolic-functions)
endfunction()

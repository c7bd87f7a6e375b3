# rayproof_direct_link_items(TARGET OUT): the link items TARGET names directly, its LINK_LIBRARIES
# (not for an interface library, which has none) and INTERFACE_LINK_LIBRARIES, as CMake holds them
# (generator expressions not unwrapped). Used by the Python module's walk of the link graph
# (python/CMakeLists.txt) and by the layer lint's dump of it (tests/lint/link_graph.cmake).
function(rayproof_direct_link_items target out)
  get_target_property(type ${target} TYPE)
  set(items "")
  foreach(prop LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
    if(type STREQUAL "INTERFACE_LIBRARY" AND prop STREQUAL "LINK_LIBRARIES")
      continue()
    endif()
    get_target_property(v ${target} ${prop})
    if(v)
      list(APPEND items ${v})
    endif()
  endforeach()
  set(${out} "${items}" PARENT_SCOPE)
endfunction()

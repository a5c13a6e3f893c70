# cmake -DFROM=<lcm-gen's python/hunav> -DTO=<build/python/hunav> -P copy_messages.cmake
# Copies lcm-gen's message modules into the hunav package, its __init__.py as _messages.py, and
# removes the modules of types that no longer exist (a removed .lcm file).
file(GLOB generated RELATIVE ${FROM} ${FROM}/*.py)
file(GLOB previous RELATIVE ${TO} ${TO}/*_t.py)
foreach(name IN LISTS previous)
  if(NOT name IN_LIST generated)
    file(REMOVE ${TO}/${name})
  endif()
endforeach()
file(MAKE_DIRECTORY ${TO})
foreach(name IN LISTS generated)
  if(name STREQUAL "__init__.py")
    configure_file(${FROM}/${name} ${TO}/_messages.py COPYONLY)
  else()
    configure_file(${FROM}/${name} ${TO}/${name} COPYONLY)
  endif()
endforeach()

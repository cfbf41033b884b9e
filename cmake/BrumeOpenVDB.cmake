# OpenVDB::openvdb. Debian's libopenvdb-dev ships no OpenVDBConfig.cmake, only a FindOpenVDB.cmake in its
# multiarch folder, /usr/lib/<multiarch>/cmake/OpenVDB (x86_64-linux-gnu, aarch64-linux-gnu, ...; GUIDE
# section 5). Look for that folder under every prefix CMake searches, with this compiler's multiarch
# name; -DBRUME_OPENVDB_MODULE_DIR=<folder> overrides the search.
set(brume_openvdb_dirs)
foreach(prefix IN LISTS CMAKE_PREFIX_PATH CMAKE_SYSTEM_PREFIX_PATH)
  if(CMAKE_LIBRARY_ARCHITECTURE)
    list(APPEND brume_openvdb_dirs ${prefix}/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB)
  endif()
  list(APPEND brume_openvdb_dirs ${prefix}/lib/cmake/OpenVDB ${prefix}/lib64/cmake/OpenVDB)
endforeach()
list(REMOVE_DUPLICATES brume_openvdb_dirs)
find_path(BRUME_OPENVDB_MODULE_DIR NAMES FindOpenVDB.cmake PATHS ${brume_openvdb_dirs} NO_DEFAULT_PATH
          DOC "Folder holding OpenVDB's FindOpenVDB.cmake (Debian: libopenvdb-dev)")
if(NOT BRUME_OPENVDB_MODULE_DIR)
  list(JOIN brume_openvdb_dirs "\n    " brume_openvdb_dirs_text)
  message(FATAL_ERROR
    "OpenVDB's FindOpenVDB.cmake was not found. On Debian or Ubuntu install the package libopenvdb-dev "
    "(with libboost-dev and libboost-iostreams-dev; .ci/install-deps installs them all), or pass "
    "-DBRUME_OPENVDB_MODULE_DIR=<folder holding FindOpenVDB.cmake>. Searched:\n    ${brume_openvdb_dirs_text}")
endif()
# Only for this find: that folder also holds FindOpenEXR.cmake and FindTBB.cmake, which later find_package
# calls elsewhere should not pick up by accident.
set(brume_saved_module_path ${CMAKE_MODULE_PATH})
list(APPEND CMAKE_MODULE_PATH ${BRUME_OPENVDB_MODULE_DIR})
find_package(OpenVDB REQUIRED)
set(CMAKE_MODULE_PATH ${brume_saved_module_path})
if(NOT TARGET OpenVDB::openvdb)
  message(FATAL_ERROR "${BRUME_OPENVDB_MODULE_DIR}/FindOpenVDB.cmake defined no OpenVDB::openvdb target")
endif()

# Where the C++ files under sim/, render/ and app/ go: each folder feeds one target, and subfolders are not
# included. The libraries take their sources from this table (brume_add_folder_sources), and after all the
# targets exist, brume_check_source_layout fails configuration on any .cpp/.h that is not in exactly the
# target its folder names, so a new file cannot end up in no library. To add a folder, add a line here.
set(BRUME_SOURCE_FOLDERS
  sim            brume_sim
  sim/vdb        brume_vdb
  render         brume_render_cpu
  render/vk      brume_render_vk
  render/frame   brume_render_vk
  render/methods brume_render_vk
  app            brume)
# The targets that need Vulkan. With BRUME_CPU_ONLY they are not defined, so their folders are not built.
set(BRUME_VULKAN_TARGETS brume_render_vk brume_spirv brume_shaders brume)

# Splits BRUME_SOURCE_FOLDERS into two parallel lists, <folders_var> and <targets_var>.
function(_brume_source_rules folders_var targets_var)
  list(LENGTH BRUME_SOURCE_FOLDERS n)
  math(EXPR odd "${n} % 2")
  if(odd)
    message(FATAL_ERROR "BRUME_SOURCE_FOLDERS in cmake/BrumeSources.cmake must be folder/target pairs")
  endif()
  set(folders)
  set(targets)
  math(EXPR last "${n} - 1")
  foreach(i RANGE 0 ${last} 2)
    math(EXPR j "${i} + 1")
    list(GET BRUME_SOURCE_FOLDERS ${i} folder)
    list(GET BRUME_SOURCE_FOLDERS ${j} target)
    if(folder IN_LIST folders)
      message(FATAL_ERROR "cmake/BrumeSources.cmake: folder ${folder} has more than one rule")
    endif()
    list(APPEND folders ${folder})
    list(APPEND targets ${target})
  endforeach()
  set(${folders_var} ${folders} PARENT_SCOPE)
  set(${targets_var} ${targets} PARENT_SCOPE)
endfunction()

# Adds to <target> the .cpp and .h files of every folder that BRUME_SOURCE_FOLDERS assigns to it. The globs
# use CONFIGURE_DEPENDS: adding or removing a file re-runs CMake at the next build. A folder that does not
# exist yet (render/frame before its first file) simply adds nothing.
function(brume_add_folder_sources target)
  _brume_source_rules(folders targets)
  set(found FALSE)
  foreach(folder target_of IN ZIP_LISTS folders targets)
    if(NOT target_of STREQUAL target)
      continue()
    endif()
    set(found TRUE)
    file(GLOB sources CONFIGURE_DEPENDS
         ${PROJECT_SOURCE_DIR}/${folder}/*.cpp ${PROJECT_SOURCE_DIR}/${folder}/*.h)
    if(sources)
      target_sources(${target} PRIVATE ${sources})
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "brume_add_folder_sources(${target}): no folder in BRUME_SOURCE_FOLDERS "
                        "(cmake/BrumeSources.cmake) names ${target}")
  endif()
endfunction()

# Fails configuration, naming each file, when a C or C++ file under sim/, render/ or app/ is in a folder
# without a rule, has an extension other than .cpp/.h, or is not in exactly one target: the one its folder
# names. In a CPU-only build the Vulkan targets' folders are expected to be in no target. Call it once, at
# the end of the top-level CMakeLists.txt, after every target exists.
function(brume_check_source_layout)
  _brume_source_rules(folders targets)
  # Every target that takes sources by folder, and the absolute paths of the sources each one has.
  set(known_targets ${targets})
  list(REMOVE_DUPLICATES known_targets)
  foreach(t IN LISTS known_targets)
    set(sources_of_${t})
    if(NOT TARGET ${t})
      if(NOT (BRUME_CPU_ONLY AND t IN_LIST BRUME_VULKAN_TARGETS))
        message(FATAL_ERROR "cmake/BrumeSources.cmake names target ${t}, which no CMakeLists.txt defines")
      endif()
      continue()
    endif()
    get_target_property(t_sources ${t} SOURCES)
    get_target_property(t_dir ${t} SOURCE_DIR)
    foreach(s IN LISTS t_sources)
      cmake_path(ABSOLUTE_PATH s BASE_DIRECTORY ${t_dir} NORMALIZE OUTPUT_VARIABLE abs)
      list(APPEND sources_of_${t} ${abs})
    endforeach()
  endforeach()

  file(GLOB_RECURSE files CONFIGURE_DEPENDS LIST_DIRECTORIES false RELATIVE ${PROJECT_SOURCE_DIR}
       ${PROJECT_SOURCE_DIR}/sim/* ${PROJECT_SOURCE_DIR}/render/* ${PROJECT_SOURCE_DIR}/app/*)
  list(SORT files)
  set(problems)
  foreach(file IN LISTS files)
    if(NOT file MATCHES "\\.(cpp|h|c|cc|cxx|c\\+\\+|hpp|hh|hxx|h\\+\\+|inl|ipp|tpp)$")
      continue()  # CMakeLists.txt, notes, data
    endif()
    if(NOT file MATCHES "\\.(cpp|h)$")
      list(APPEND problems "${file}: Brume's C++ files are .cpp and .h (rename it)")
      continue()
    endif()
    cmake_path(GET file PARENT_PATH folder)
    list(FIND folders "${folder}" at)
    if(at EQUAL -1)
      list(APPEND problems "${file}: folder ${folder}/ has no rule, so the file is in no library")
      continue()
    endif()
    list(GET targets ${at} want)
    set(abs ${PROJECT_SOURCE_DIR}/${file})
    set(in)
    foreach(t IN LISTS known_targets)
      if(abs IN_LIST sources_of_${t})
        list(APPEND in ${t})
      endif()
    endforeach()
    if(NOT TARGET ${want})
      # A Vulkan target in a CPU-only build (checked above): its files must be in no CPU target either.
      if(in)
        list(JOIN in ", " in_text)
        list(APPEND problems "${file}: belongs to ${want} (not built with BRUME_CPU_ONLY) but is in ${in_text}")
      endif()
    elseif(NOT in STREQUAL want)
      if(in)
        list(JOIN in ", " in_text)
      else()
        set(in_text "no target")
      endif()
      list(APPEND problems "${file}: its folder's rule says ${want}, but it is in ${in_text}")
    endif()
  endforeach()

  if(problems)
    set(rules_text "")
    foreach(folder t IN ZIP_LISTS folders targets)
      string(APPEND rules_text "    ${folder}/*.cpp, *.h -> ${t}\n")
    endforeach()
    list(JOIN problems "\n    " problems_text)
    message(FATAL_ERROR "Source layout: these files would not be built as the layout says:\n"
                        "    ${problems_text}\n"
                        "The folder rules (BRUME_SOURCE_FOLDERS in cmake/BrumeSources.cmake):\n"
                        "${rules_text}"
                        "Move each file into one of these folders, or add a rule for its folder there.")
  endif()
endfunction()

# Writes OUTPUT from INPUT with the git revision of SOURCE_DIR at build time
# (not configure time, so a rebuild after a commit records the new revision).
# The file is rewritten only when its text changes, so a build with nothing
# new recompiles nothing.
set(GRANFLOW_REVISION "no revision")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty --abbrev=12
                  WORKING_DIRECTORY "${SOURCE_DIR}" OUTPUT_VARIABLE revision
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(revision)
    set(GRANFLOW_REVISION "${revision}")
  endif()
endif()
configure_file("${INPUT}" "${OUTPUT}.new" @ONLY)
file(COPY_FILE "${OUTPUT}.new" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.new")

# Third-party source, fetched at configure time from Debian's source packages (version pinned,
# SHA-256 checked) and never committed: the same tarball for every build and every target.
#
# The tarballs go to one download cache (KILOLOOP_THIRD_PARTY_CACHE, default build/third_party of
# the source tree), shared by the build directories (build/py, build/asan, build/cpp,
# build/firmware/core): downloaded once, checked every time. Offline or for a cross build, put the
# tarball there by hand (the hash is still checked).
set(KILOLOOP_THIRD_PARTY_CACHE "${CMAKE_CURRENT_SOURCE_DIR}/build/third_party" CACHE PATH
    "where the third-party source tarballs are downloaded to (shared by the build directories)")

# kiloloop_fetch_source(<out_var> NAME <file> SHA256 <hash> URLS <url>... [PATTERNS <glob>...])
# Downloads <file> (the first URL that answers, into the cache; a file already there with the right
# hash is reused), extracts it (only the members matching PATTERNS, if given) into
# ${CMAKE_BINARY_DIR}/third_party/<file minus extension> and sets <out_var> to that directory's
# one top-level folder.
function(kiloloop_fetch_source out_var)
  cmake_parse_arguments(ARG "" "NAME;SHA256" "URLS;PATTERNS" ${ARGN})
  set(tarball "${KILOLOOP_THIRD_PARTY_CACHE}/${ARG_NAME}")
  file(MAKE_DIRECTORY "${KILOLOOP_THIRD_PARTY_CACHE}")
  # Two builds may configure at once (`make test`: the sanitizer stage beside the wheel).
  file(LOCK "${tarball}.lock" GUARD FUNCTION TIMEOUT 600)
  set(have OFF)
  if(EXISTS "${tarball}")
    file(SHA256 "${tarball}" got)
    if(got STREQUAL ARG_SHA256)
      set(have ON)
    endif()
  endif()
  if(NOT have)
    foreach(url IN LISTS ARG_URLS)
      message(STATUS "kiloloop: downloading ${url}")
      file(DOWNLOAD "${url}" "${tarball}.part" STATUS status TIMEOUT 300)
      list(GET status 0 code)
      if(code EQUAL 0)
        file(SHA256 "${tarball}.part" got)
        if(got STREQUAL ARG_SHA256)
          file(RENAME "${tarball}.part" "${tarball}")
          set(have ON)
          break()
        endif()
        message(WARNING "kiloloop: ${url}: SHA-256 ${got}, expected ${ARG_SHA256}")
      else()
        message(WARNING "kiloloop: ${url}: ${status}")
      endif()
    endforeach()
    file(REMOVE "${tarball}.part")
  endif()
  if(NOT have)
    message(FATAL_ERROR "kiloloop: no ${ARG_NAME} with SHA-256 ${ARG_SHA256}; tried ${ARG_URLS}. "
                        "Put the file into ${KILOLOOP_THIRD_PARTY_CACHE} (the hash is checked).")
  endif()
  string(REGEX REPLACE "\\.(tar\\.gz|tar\\.xz|tgz)$" "" stem "${ARG_NAME}")
  set(dest "${CMAKE_BINARY_DIR}/third_party/${stem}")
  if(EXISTS "${dest}/.sha256")
    file(READ "${dest}/.sha256" extracted)
  else()
    set(extracted "")
  endif()
  if(NOT extracted STREQUAL ARG_SHA256)
    file(REMOVE_RECURSE "${dest}")
    if(ARG_PATTERNS)
      file(ARCHIVE_EXTRACT INPUT "${tarball}" DESTINATION "${dest}" PATTERNS ${ARG_PATTERNS})
    else()
      file(ARCHIVE_EXTRACT INPUT "${tarball}" DESTINATION "${dest}")
    endif()
    file(WRITE "${dest}/.sha256" "${ARG_SHA256}")
  endif()
  file(GLOB top LIST_DIRECTORIES true "${dest}/*")
  list(FILTER top EXCLUDE REGEX "/\\.sha256$")
  list(LENGTH top n)
  if(NOT n EQUAL 1)
    message(FATAL_ERROR "kiloloop: ${ARG_NAME} does not hold one top-level folder: ${top}")
  endif()
  set(${out_var} "${top}" PARENT_SCOPE)
endfunction()

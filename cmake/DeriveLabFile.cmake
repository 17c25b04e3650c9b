# Derives a lab file from another (deploy/lab.yaml), changing only the values of the keys
# named, so what the lab is (its processes, ports, devices, comments) stays written once.
# Every lab file the project ships is derived this way: the installed one here, and the
# others (compose, several hosts) with their own rewrites.
#
#   cmake -DINPUT=deploy/lab.yaml -DOUTPUT=FILE
#         -DREWRITE="lab.calibration=share/igms/cal.yaml|lab.database=var/lib/igms/db"
#         [-DPREFIX=/usr/local] [-DNOTE="comment lines put first"] -P cmake/DeriveLabFile.cmake
#
# REWRITE is KEY=VALUE pairs separated by '|'; KEY is dotted (processes.video.sim.scene). A
# key the input does not have is an error, so a renamed key cannot silently go unrewritten.
# With PREFIX, a relative VALUE becomes PREFIX/VALUE (as GNUInstallDirs has it, etc/ and var/
# under the prefix /usr are /etc and /var). OUTPUT is written only when its text changes.
# Also include()-able with those variables set: igms_install_lab_file (cmake/IgmsHelpers.cmake)
# derives the installed lab file at install time, under the prefix chosen then.

# Today's rules (empty list elements kept: blank lines), whoever runs or includes this.
cmake_policy(PUSH)
cmake_policy(VERSION 3.25)

if(NOT DEFINED INPUT OR NOT DEFINED OUTPUT)
  message(FATAL_ERROR "DeriveLabFile: set INPUT and OUTPUT")
endif()
if(NOT EXISTS "${INPUT}")
  message(FATAL_ERROR "DeriveLabFile: no input lab file ${INPUT}")
endif()

# CMake lists split on ';' and keep '[...]' together: hide both while the text is a list.
string(ASCII 1 _semicolon)
string(ASCII 2 _open)
string(ASCII 3 _close)
file(READ "${INPUT}" _text)
string(REPLACE ";" "${_semicolon}" _text "${_text}")
string(REPLACE "[" "${_open}" _text "${_text}")
string(REPLACE "]" "${_close}" _text "${_text}")
string(REPLACE "\n" ";" _lines "${_text}")

# A YAML scalar for VALUE: plain when it is a simple path, double-quoted otherwise.
function(_igms_yaml_scalar value out)
  if(value MATCHES "^[A-Za-z0-9_./+-]+$")
    set(${out} "${value}" PARENT_SCOPE)
  else()
    string(REPLACE "\\" "\\\\" value "${value}")
    string(REPLACE "\"" "\\\"" value "${value}")
    set(${out} "\"${value}\"" PARENT_SCOPE)
  endif()
endfunction()

string(REPLACE "|" ";" _rewrites "${REWRITE}")
foreach(_rewrite IN LISTS _rewrites)
  if(NOT _rewrite MATCHES "^([^=]+)=(.*)$")
    message(FATAL_ERROR "DeriveLabFile: '${_rewrite}' is not KEY=VALUE")
  endif()
  set(_key "${CMAKE_MATCH_1}")
  set(_value "${CMAKE_MATCH_2}")
  if(DEFINED PREFIX AND NOT PREFIX STREQUAL "" AND NOT _value STREQUAL ""
     AND NOT IS_ABSOLUTE "${_value}")
    if(PREFIX STREQUAL "/usr" AND _value MATCHES "^(etc|var)/")
      set(_value "/${_value}")
    else()
      set(_value "${PREFIX}/${_value}")
    endif()
  endif()
  _igms_yaml_scalar("${_value}" _value)
  string(REPLACE "." ";" _parts "${_key}")
  list(LENGTH _parts _depth)
  # Walk down the key's parts: each is a direct child of the block found for the one before.
  set(_part 0)
  set(_parent_indent -1)
  set(_child_indent -1)
  set(_found -1)
  set(_index -1)
  foreach(_line IN LISTS _lines)
    math(EXPR _index "${_index} + 1")
    if(_line MATCHES "^ *(#.*)?$")
      continue()  # blank or comment
    endif()
    string(REGEX MATCH "^ +" _spaces "${_line}")
    string(LENGTH "${_spaces}" _indent)
    if(_indent LESS_EQUAL _parent_indent)
      break()  # the block ended without the key
    endif()
    if(_child_indent EQUAL -1)
      set(_child_indent ${_indent})
    endif()
    if(NOT _indent EQUAL _child_indent)
      continue()  # deeper: inside a sibling's block
    endif()
    list(GET _parts ${_part} _name)
    if(_line MATCHES "^ *([A-Za-z0-9_-]+):" AND CMAKE_MATCH_1 STREQUAL _name)
      math(EXPR _part "${_part} + 1")
      if(_part EQUAL _depth)
        set(_found ${_index})
        break()
      endif()
      set(_parent_indent ${_indent})
      set(_child_indent -1)
    endif()
  endforeach()
  if(_found EQUAL -1)
    message(FATAL_ERROR "DeriveLabFile: ${INPUT} has no key ${_key} to rewrite")
  endif()
  list(GET _lines ${_found} _line)
  list(GET _parts -1 _name)
  set(_comment "")
  # Keeps the line's comment: what follows the old value (quoted, or plain without '#').
  if(_line MATCHES "^ *[A-Za-z0-9_-]+:( *(\"[^\"]*\"|'[^']*'|[^#]*[^ #])?)( +#.*)$")
    set(_comment "${CMAKE_MATCH_3}")
  endif()
  list(REMOVE_AT _lines ${_found})
  list(INSERT _lines ${_found} "${_spaces}${_name}: ${_value}${_comment}")
endforeach()

string(REPLACE ";" "\n" _text "${_lines}")
string(REPLACE "${_semicolon}" ";" _text "${_text}")
string(REPLACE "${_open}" "[" _text "${_text}")
string(REPLACE "${_close}" "]" _text "${_text}")
if(DEFINED NOTE AND NOT NOTE STREQUAL "")
  string(REPLACE "\n" "\n# " _note "${NOTE}")
  set(_text "# ${_note}\n${_text}")
endif()
set(_old "")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" _old)
endif()
if(NOT _old STREQUAL _text)
  file(WRITE "${OUTPUT}" "${_text}")
endif()
cmake_policy(POP)

# SPDX-License-Identifier: MIT
# cmake -DDOC=<markdown file> -DTABLE=<generated table> -DNAME=<marker name> [-DUPDATE=ON] -P this
# The part of DOC between "<!-- generated: NAME -->" and "<!-- end generated: NAME -->" must equal
# TABLE (written by the configure step); with UPDATE=ON it is replaced by TABLE.
file(READ ${DOC} doc)
file(READ ${TABLE} table)
set(begin "<!-- generated: ${NAME} -->\n")
set(end "<!-- end generated: ${NAME} -->")
string(FIND "${doc}" "${begin}" i)
string(FIND "${doc}" "${end}" j)
if(i EQUAL -1 OR j EQUAL -1 OR j LESS i)
  message(FATAL_ERROR "${DOC}: no \"${begin}\" ... \"${end}\" markers")
endif()
string(LENGTH "${begin}" begin_length)
math(EXPR body_start "${i} + ${begin_length}")
math(EXPR body_length "${j} - ${body_start}")
string(SUBSTRING "${doc}" ${body_start} ${body_length} body)
if(body STREQUAL table)
  return()
endif()
if(UPDATE)
  string(SUBSTRING "${doc}" 0 ${body_start} head)
  string(SUBSTRING "${doc}" ${j} -1 tail)
  file(WRITE ${DOC} "${head}${table}${tail}")
  message(STATUS "${DOC}: table ${NAME} rewritten from ${TABLE}")
else()
  message(FATAL_ERROR "${DOC}: the table \"${NAME}\" differs from what the build declares "
                      "(${TABLE}); run scripts/update-architecture-doc.sh\n--- doc:\n${body}--- build:\n${table}")
endif()

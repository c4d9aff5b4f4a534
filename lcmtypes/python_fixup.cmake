# cmake -DFILES="a.py;b.py" -P python_fixup.cmake
#
# Debian 12's lcm-gen 1.3.1 decodes a boolean array in Python as `map(bool, struct.unpack(...))`:
# on Python 3 that is a one-shot iterator, not a list (com_estimate_t.found[0] raises TypeError,
# and a second look finds it empty). LCM fixed its generator later (a list comprehension); this
# step makes the same change to the generated files and nothing else, and fails if the
# generator's output no longer has the expected form. tests/python/decode_check.py checks every
# field of every type against the C encoding.
foreach(f IN LISTS FILES)
  file(READ ${f} text)
  string(REGEX REPLACE "= map\\(bool, ([^\n]*)\\)\n" "= list(map(bool, \\1))\n" fixed "${text}")
  string(FIND "${fixed}" "= map(bool" left)
  if(NOT left EQUAL -1)
    message(FATAL_ERROR "${f}: a boolean array decode of an unexpected form")
  endif()
  if(NOT fixed STREQUAL text)
    file(WRITE ${f} "${fixed}")
  endif()
endforeach()

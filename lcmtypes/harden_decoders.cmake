# Run after lcm-gen on one generated header (cmake -DHEADER=... -P this):
# lcm-gen checks a string's length field only against the bytes left, so a
# zero or negative one passes; `length - 1` then asks std::string for an
# impossible size (an exception out of the decoder) or, for INT32_MIN,
# overflows (found by fuzz_lcm_decode). A string is encoded with its NUL:
# its length is at least 1.
file(READ "${HEADER}" text)
string(REGEX REPLACE "if\\((__[A-Za-z0-9_]+_len__) > maxlen - pos\\) return -1;"
       "if(\\1 < 1 || \\1 > maxlen - pos) return -1;" hardened "${text}")
file(WRITE "${HEADER}" "${hardened}")

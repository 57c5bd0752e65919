file(REMOVE_RECURSE
  "liblsalepm_lib.a"
)

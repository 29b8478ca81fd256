file(REMOVE_RECURSE
  "libvi_core.a"
)

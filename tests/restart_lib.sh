# Helpers for the restart tests (sourced).
# derive NEW BASE RUN_VARS NAME: copy deck BASE to NEW.nml with extra &run
# variables appended and &output replaced by dir = 'out', name = NAME.
derive() {
  local new=$1 base=$2 vars=$3 name=$4
  sed -e "s|^\(&run .*\)/ *\$|\1, $vars /|" \
      -e "s|^&output.*|\&output dir = 'out', name = '$name' /|" "$base" > "$new.nml"
  grep -q "$vars" "$new.nml" || { echo "FAIL: could not derive $new.nml from $base"; exit 1; }
}
fail() { echo "FAIL: $*"; exit 1; }

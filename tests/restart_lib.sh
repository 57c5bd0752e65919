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
# final_frame NAME: the highest-numbered frame out/NAME_NNNNN.h5 (a run's
# final frame; a split run lists the first segment's final frame too, so the
# numbers of a straight and a split run's final frames may differ).
final_frame() {
  ls out/"$1"_[0-9][0-9][0-9][0-9][0-9].h5 2> /dev/null | sort | tail -1
}

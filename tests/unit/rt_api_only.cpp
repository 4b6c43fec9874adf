// A renderer's unit that includes <spectralize/rt.hpp> without SPECTRALIZE_RT_IMPLEMENTATION:
// a texture lookup (fetch, then eval4), a table loaded and a spectrum's samples. The test
// rt_api_header (rt_api_header.cmake) reads this object's symbols: it calls the loader but
// defines none of rt_impl.hpp, and fetch and eval4 are inline in it.
#include <spectralize/rt.hpp>

#include <cstddef>

int rt_api_only_lookup(const spz::TableView& view, const float rgb[3], const float lambda_nm[4],
                       float out[4]) {
  spz::Spectrum s;
  const int status = view.fetch(rgb, s);
  spz::eval4(s, lambda_nm, out);
  return status;
}

int rt_api_only_fetch_eval4(const spz::TableView& view, const float rgb[3],
                            const float lambda_nm[4], float out[4]) {
  return view.fetch_eval4(rgb, lambda_nm, out);
}

std::size_t rt_api_only_load(const char* path, float* out, std::size_t capacity) {
  spz::Table table;
  if (!table.load(path)) return 0;
  const float rgb[3] = {0.2f, 0.5f, 0.1f};
  spz::Spectrum s;
  table.view().fetch(rgb, s);
  return spz::samples(s, out, capacity);
}

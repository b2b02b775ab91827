// GDAL in one place: see gdal_support.hpp.
#include "io/gdal_support.hpp"

#include <mutex>
#include <string>
#include <string_view>

namespace tincdt::io::detail {
namespace {

constexpr std::size_t kMaxWarnings = 20;

}  // namespace

int CPL_STDCALL GdalProgress::report(double fraction, const char*, void* data) {
  auto* self = static_cast<GdalProgress*>(data);
  if ((*self->fn_)(self->stage_, fraction)) return TRUE;
  self->cancelled_ = true;
  return FALSE;
}

void register_gdal_drivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

std::string one_line(std::string_view text) {
  std::string s;
  s.reserve(text.size());
  for (const char c : text) {
    const bool blank = c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    if (blank) {
      if (!s.empty() && s.back() != ' ') s += ' ';
    } else {
      s += c;
    }
  }
  if (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string last_gdal_message(const char* fallback) {
  const char* msg = CPLGetLastErrorMsg();
  std::string text = msg != nullptr ? one_line(msg) : std::string();
  return text.empty() ? std::string(fallback) : text;
}

OGRSpatialReference gis_order_srs() {
  OGRSpatialReference srs;
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

bool import_wkt(OGRSpatialReference& srs, const std::string& wkt) {
  return srs.importFromWkt(wkt.c_str()) == OGRERR_NONE;
}

GdalMessages::GdalMessages() {
  CPLPushErrorHandlerEx(&GdalMessages::handle, this);
  CPLErrorReset();
}

GdalMessages::~GdalMessages() {
  CPLPopErrorHandler();
}

void CPL_STDCALL GdalMessages::handle(CPLErr level, CPLErrorNum, const char* msg) {
  auto* self = static_cast<GdalMessages*>(CPLGetErrorHandlerUserData());
  if (self == nullptr) return;
  if (level == CE_Failure || level == CE_Fatal) {
    if (!self->failed_) self->failure_ = one_line(msg != nullptr ? msg : "");
    self->failed_ = true;
  } else if (level == CE_Warning && self->warnings_.size() < kMaxWarnings) {
    self->warnings_.push_back(one_line(msg != nullptr ? msg : ""));
  }
}

}  // namespace tincdt::io::detail

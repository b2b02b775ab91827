// Vector files and OGR in the tests: small sources written for the reader tests (layers of WKT
// features with a numeric ELEV attribute and one text attribute), and the files the writers
// wrote, opened again to read back. Header-only, for the tests.
#pragma once

#include <cpl_error.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace tincdt::test {

// A vector file opened read-only with one GDAL driver; ds is null when it cannot be.
struct VectorFile {
  VectorFile(const std::string& path, const char* driver) {
    GDALAllRegister();
    const char* const drivers[] = {driver, nullptr};
    ds = GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, drivers, nullptr, nullptr);
  }
  ~VectorFile() {
    if (ds != nullptr) GDALClose(ds);
  }
  VectorFile(const VectorFile&) = delete;
  VectorFile& operator=(const VectorFile&) = delete;
  OGRLayerH layer() const { return GDALDatasetGetLayer(ds, 0); }
  OGRLayerH layer(const char* name) const { return GDALDatasetGetLayerByName(ds, name); }
  GDALDatasetH ds = nullptr;
};

// "AUTHORITY:CODE" of the CRS of LAYER ("EPSG:2949"), "" when the layer has none.
inline std::string layer_crs_code(OGRLayerH layer) {
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(layer);
  if (srs == nullptr) return "";
  const char* authority = OSRGetAuthorityName(srs, nullptr);
  const char* code = OSRGetAuthorityCode(srs, nullptr);
  return std::string(authority != nullptr ? authority : "?") + ":" + (code != nullptr ? code : "?");
}

struct VectorFeature {
  std::string wkt;             // empty = no geometry
  std::optional<double> elev;  // ELEV; nullopt = NULL
  std::int64_t fid = -1;       // -1 = let the driver choose
  std::string text = "x";      // the text attribute
  int nan_vertex = -1;         // set this vertex's x to NaN after parsing the WKT
};

struct VectorLayer {
  std::string name;
  std::vector<VectorFeature> features;
  int epsg = 0;  // 0 = no CRS
};

// Writes LAYERS to a fresh file PATH with DRIVER, each layer with the fields ELEV (real) and
// TEXT_FIELD (string); returns PATH. LAYER is any type with `name`, `features` (of a type that
// is or derives from VectorFeature) and `epsg`.
template <class Layer>
std::string write_vector(const std::filesystem::path& path, const std::vector<Layer>& layers,
                         const char* driver_name, const char* text_field) {
  GDALAllRegister();
  std::filesystem::create_directories(path.parent_path());
  std::filesystem::remove(path);
  GDALDriverH driver = GDALGetDriverByName(driver_name);
  EXPECT_NE(driver, nullptr) << driver_name;
  GDALDatasetH ds = GDALCreate(driver, path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  EXPECT_NE(ds, nullptr) << CPLGetLastErrorMsg();
  if (ds == nullptr) return path.string();
  for (const Layer& spec : layers) {
    OGRSpatialReferenceH srs = nullptr;
    if (spec.epsg != 0) {
      srs = OSRNewSpatialReference(nullptr);
      OSRImportFromEPSG(srs, spec.epsg);
    }
    OGRLayerH layer = GDALDatasetCreateLayer(ds, spec.name.c_str(), srs, wkbUnknown, nullptr);
    if (srs != nullptr) OSRRelease(srs);
    EXPECT_NE(layer, nullptr) << CPLGetLastErrorMsg();
    if (layer == nullptr) continue;
    OGRFieldDefnH elev = OGR_Fld_Create("ELEV", OFTReal);
    OGRFieldDefnH text = OGR_Fld_Create(text_field, OFTString);
    OGR_L_CreateField(layer, elev, TRUE);
    OGR_L_CreateField(layer, text, TRUE);
    OGR_Fld_Destroy(elev);
    OGR_Fld_Destroy(text);
    for (const VectorFeature& f : spec.features) {
      OGRFeatureH feature = OGR_F_Create(OGR_L_GetLayerDefn(layer));
      if (f.fid >= 0) OGR_F_SetFID(feature, f.fid);
      if (f.elev) {
        OGR_F_SetFieldDouble(feature, 0, *f.elev);
      } else {
        OGR_F_SetFieldNull(feature, 0);
      }
      OGR_F_SetFieldString(feature, 1, f.text.c_str());
      if (!f.wkt.empty()) {
        OGRGeometryH g = nullptr;
        char* wkt = const_cast<char*>(f.wkt.c_str());
        EXPECT_EQ(OGR_G_CreateFromWkt(&wkt, nullptr, &g), OGRERR_NONE) << f.wkt;
        if (g != nullptr && f.nan_vertex >= 0) {
          OGR_G_SetPoint(g, f.nan_vertex, std::numeric_limits<double>::quiet_NaN(), 0.0, 1.0);
        }
        OGR_F_SetGeometryDirectly(feature, g);
      }
      EXPECT_EQ(OGR_L_CreateFeature(layer, feature), OGRERR_NONE) << CPLGetLastErrorMsg();
      OGR_F_Destroy(feature);
    }
  }
  GDALClose(ds);
  return path.string();
}

}  // namespace tincdt::test

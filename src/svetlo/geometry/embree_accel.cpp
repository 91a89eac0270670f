#include "svetlo/geometry/embree_accel.h"

#include <stdexcept>
#include <string>

#ifdef SVETLO_HAS_EMBREE
#include <embree3/rtcore.h>

#include <limits>
#endif

#include "svetlo/core/parallel.h"

namespace svetlo {

#ifdef SVETLO_HAS_EMBREE

namespace {

/// What the shape callbacks need: the geometry and the ids of its bounded shapes.
struct ShapeTable {
    const Geometry* geometry = nullptr;
    std::vector<uint32_t> ids;
};

Ray to_ray(const RTCRay& r) {
    return Ray{vec3(r.org_x, r.org_y, r.org_z), vec3(r.dir_x, r.dir_y, r.dir_z), r.tfar};
}

void shape_bounds_cb(const RTCBoundsFunctionArguments* args) {
    const auto* table = static_cast<const ShapeTable*>(args->geometryUserPtr);
    Bounds3 b = table->geometry->primitive_bounds(table->ids[args->primID]);
    *args->bounds_o = RTCBounds{b.min.x, b.min.y, b.min.z, 0.0f, b.max.x, b.max.y, b.max.z, 0.0f};
}

// svetlo only calls rtcIntersect1 / rtcOccluded1, so the callbacks see one ray (N == 1).
void shape_intersect_cb(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* table = static_cast<const ShapeTable*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    Ray ray = to_ray(rh->ray);
    ShapeHit sh;
    const Geometry& g = *table->geometry;
    if (!intersect_shape(g.shape(table->ids[args->primID]), ray, rh->ray.tfar, sh)) return;
    if (sh.t < rh->ray.tnear) return;
    rh->ray.tfar = sh.t;
    rh->hit.u = 0.0f;  // svetlo re-evaluates the winning primitive
    rh->hit.v = 0.0f;
    rh->hit.Ng_x = rh->hit.Ng_y = rh->hit.Ng_z = 0.0f;
    rh->hit.primID = args->primID;
    rh->hit.geomID = args->geomID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void shape_occluded_cb(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* table = static_cast<const ShapeTable*>(args->geometryUserPtr);
    auto* r = reinterpret_cast<RTCRay*>(args->ray);
    ShapeHit sh;
    const Geometry& g = *table->geometry;
    if (intersect_shape(g.shape(table->ids[args->primID]), to_ray(*r), r->tfar, sh) &&
        sh.t >= r->tnear) {
        r->tfar = -std::numeric_limits<float>::infinity();
    }
}

class EmbreeAccel final : public Accel {
public:
    EmbreeAccel(const Geometry& geometry, int threads) : geometry_(geometry) {
        std::string config =
            "threads=" + std::to_string(resolve_threads(threads)) + ",set_affinity=0";
        device_ = rtcNewDevice(config.c_str());
        if (!device_) throw std::runtime_error("Embree: cannot create a device");
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
        uint32_t triangles = geometry.triangle_count();
        if (triangles > 0) {
            RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            // Embree's own buffers (with the padding it reads past the last vertex).
            auto* v = static_cast<float*>(
                rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), geometry.positions.size()));
            for (size_t k = 0; k < geometry.positions.size(); ++k) {
                v[3 * k] = geometry.positions[k].x;
                v[3 * k + 1] = geometry.positions[k].y;
                v[3 * k + 2] = geometry.positions[k].z;
            }
            auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
                mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles));
            std::copy(geometry.indices.begin(), geometry.indices.end(), idx);
            rtcCommitGeometry(mesh);
            triangle_geom_ = rtcAttachGeometry(scene_, mesh);
            rtcReleaseGeometry(mesh);
        }
        shapes_.geometry = &geometry;
        for (uint32_t id : geometry.bounded_primitives()) {
            if (!geometry.is_triangle(id)) shapes_.ids.push_back(id);
        }
        if (!shapes_.ids.empty()) {
            RTCGeometry user = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(user, static_cast<unsigned>(shapes_.ids.size()));
            rtcSetGeometryUserData(user, &shapes_);
            rtcSetGeometryBoundsFunction(user, shape_bounds_cb, nullptr);
            rtcSetGeometryIntersectFunction(user, shape_intersect_cb);
            rtcSetGeometryOccludedFunction(user, shape_occluded_cb);
            rtcCommitGeometry(user);
            shape_geom_ = rtcAttachGeometry(scene_, user);
            rtcReleaseGeometry(user);
        }
        rtcCommitScene(scene_);
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
            rtcReleaseScene(scene_);
            rtcReleaseDevice(device_);
            throw std::runtime_error("Embree: the scene failed to build");
        }
    }
    ~EmbreeAccel() override {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    EmbreeAccel(const EmbreeAccel&) = delete;
    EmbreeAccel& operator=(const EmbreeAccel&) = delete;

    bool intersect(const Ray& ray, Hit& hit) const override {
        hit = Hit{};
        hit.t = ray.tmax;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh = make_rayhit(ray);
        rtcIntersect1(scene_, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        uint32_t prim =
            rh.hit.geomID == triangle_geom_ ? rh.hit.primID : shapes_.ids[rh.hit.primID];
        // Same t and barycentrics as svetlo's own structures; Embree's values only where its
        // triangle test and the watertight one disagree on an edge.
        RayPrecomputed pre(ray);
        if (!geometry_.intersect(prim, ray, pre, hit)) {
            hit.t = rh.ray.tfar;
            hit.prim = prim;
            hit.u = rh.hit.u;
            hit.v = rh.hit.v;
            hit.part = 0;
        }
        return true;
    }

    bool occluded(const Ray& ray) const override {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay r = make_rayhit(ray).ray;
        rtcOccluded1(scene_, &context, &r);
        return r.tfar < 0.0f;
    }

    size_t memory_bytes() const override { return 0; }  // Embree does not report it

private:
    static RTCRayHit make_rayhit(const Ray& ray) {
        RTCRayHit rh{};
        rh.ray.org_x = ray.o.x;
        rh.ray.org_y = ray.o.y;
        rh.ray.org_z = ray.o.z;
        rh.ray.dir_x = ray.d.x;
        rh.ray.dir_y = ray.d.y;
        rh.ray.dir_z = ray.d.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = ray.tmax;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        return rh;
    }

    const Geometry& geometry_;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    unsigned triangle_geom_ = RTC_INVALID_GEOMETRY_ID;
    unsigned shape_geom_ = RTC_INVALID_GEOMETRY_ID;
    ShapeTable shapes_;
};

}  // namespace

bool embree_available() { return true; }

std::unique_ptr<Accel> make_embree_accel(const Geometry& geometry, int threads) {
    return std::make_unique<EmbreeAccel>(geometry, threads);
}

#else

bool embree_available() { return false; }

std::unique_ptr<Accel> make_embree_accel(const Geometry&, int) {
    throw std::runtime_error("this svetlo was built without Embree");
}

#endif

}  // namespace svetlo

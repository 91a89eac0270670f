#include "svetlo/geometry/embree_accel.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

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
    rh->hit.instID[0] = args->context->instID[0];  // the placement whose prototype this is
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

/// One of Embree's scenes over a geometry's own primitives: its triangles as Embree's
/// triangle mesh, its bounded shapes as user geometry calling svetlo's intersectors. The top
/// scene is one (the world's primitives, with the placements beside them as Embree's own
/// instances), and each prototype is one, built once and instanced by every placement.
class EmbreeLevel {
public:
    EmbreeLevel(RTCDevice device, const Geometry& geometry) : geometry_(geometry) {
        scene_ = rtcNewScene(device);
        rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
        if (geometry.triangle_count() > 0) add_triangles(device);
        shapes_.geometry = &geometry;
        for (uint32_t id : geometry.bounded_primitives())
            if (!geometry.is_triangle(id)) shapes_.ids.push_back(id);
        if (!shapes_.ids.empty()) add_shapes(device);
    }
    ~EmbreeLevel() { rtcReleaseScene(scene_); }
    EmbreeLevel(const EmbreeLevel&) = delete;
    EmbreeLevel& operator=(const EmbreeLevel&) = delete;

    RTCScene scene() const { return scene_; }
    const Geometry& geometry() const { return geometry_; }

    /// The geometry's primitive that Embree's (geomID, primID) names.
    uint32_t primitive(unsigned geom, unsigned prim) const {
        return geom == triangle_geom_ ? prim : shapes_.ids[prim];
    }

private:
    void add_triangles(RTCDevice device) {
        RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree's own buffers (with the padding it reads past the last vertex).
        const auto& positions = geometry_.positions;
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                              positions.size()));
        for (size_t k = 0; k < positions.size(); ++k) {
            v[3 * k] = positions[k].x;
            v[3 * k + 1] = positions[k].y;
            v[3 * k + 2] = positions[k].z;
        }
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), geometry_.triangle_count()));
        std::copy(geometry_.indices.begin(), geometry_.indices.end(), idx);
        rtcCommitGeometry(mesh);
        triangle_geom_ = rtcAttachGeometry(scene_, mesh);
        rtcReleaseGeometry(mesh);
    }

    void add_shapes(RTCDevice device) {
        RTCGeometry user = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(user, static_cast<unsigned>(shapes_.ids.size()));
        rtcSetGeometryUserData(user, &shapes_);
        rtcSetGeometryBoundsFunction(user, shape_bounds_cb, nullptr);
        rtcSetGeometryIntersectFunction(user, shape_intersect_cb);
        rtcSetGeometryOccludedFunction(user, shape_occluded_cb);
        rtcCommitGeometry(user);
        rtcAttachGeometry(scene_, user);
        rtcReleaseGeometry(user);
    }

    const Geometry& geometry_;
    RTCScene scene_ = nullptr;
    unsigned triangle_geom_ = RTC_INVALID_GEOMETRY_ID;
    ShapeTable shapes_;  // the user geometry's data: its address must not move
};

class EmbreeAccel final : public Accel {
public:
    EmbreeAccel(const Geometry& geometry, int threads) : geometry_(geometry) {
        std::string config =
            "threads=" + std::to_string(resolve_threads(threads)) + ",set_affinity=0";
        device_ = rtcNewDevice(config.c_str());
        if (!device_) throw std::runtime_error("Embree: cannot create a device");
        rtcSetDeviceMemoryMonitorFunction(device_, count_bytes, &bytes_);
        world_ = std::make_unique<EmbreeLevel>(device_, geometry);
        for (const auto& prototype : geometry.prototypes) {
            prototypes_.push_back(std::make_unique<EmbreeLevel>(device_, *prototype));
            rtcCommitScene(prototypes_.back()->scene());
        }
        for (uint32_t k = 0; k < geometry.placements.size(); ++k) add_instance(k);
        rtcCommitScene(world_->scene());
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
            release();
            throw std::runtime_error("Embree: the scene failed to build");
        }
    }
    ~EmbreeAccel() override { release(); }
    EmbreeAccel(const EmbreeAccel&) = delete;
    EmbreeAccel& operator=(const EmbreeAccel&) = delete;

    bool intersect(const Ray& ray, Hit& hit) const override {
        hit = Hit{};
        hit.t = ray.tmax;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh = make_rayhit(ray);
        rtcIntersect1(world_->scene(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        const EmbreeLevel* level = world_.get();
        Ray local = ray;
        uint32_t instance = Hit::kNone;
        if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
            instance = instance_placement_[rh.hit.instID[0]];
            const Placement& place = geometry_.placements[instance];
            level = prototypes_[place.prototype].get();
            local = place.to_prototype_ray(ray);
        }
        const uint32_t prim = level->primitive(rh.hit.geomID, rh.hit.primID);
        // Same t and barycentrics as svetlo's own structures; Embree's values only where its
        // triangle test and the watertight one disagree on an edge.
        RayPrecomputed pre(local);
        if (!level->geometry().intersect(prim, local, pre, hit)) {
            hit.t = rh.ray.tfar;
            hit.prim = prim;
            hit.u = rh.hit.u;
            hit.v = rh.hit.v;
            hit.part = 0;
        }
        hit.instance = instance;
        return true;
    }

    bool occluded(const Ray& ray) const override {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay r = make_rayhit(ray).ray;
        rtcOccluded1(world_->scene(), &context, &r);
        return r.tfar < 0.0f;
    }

    size_t memory_bytes() const override {
        return static_cast<size_t>(std::max<ssize_t>(bytes_.load(), 0));
    }

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

    /// Places prototype `k`'s scene as Embree's instance, by the placement's matrix (column
    /// major, as glm stores it); an empty prototype is never met and is left out.
    void add_instance(uint32_t k) {
        const Placement& place = geometry_.placements[k];
        if (place.bounds.empty()) return;
        RTCGeometry instance = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(instance, prototypes_[place.prototype]->scene());
        rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                                &place.to_world.matrix[0][0]);
        rtcCommitGeometry(instance);
        const unsigned id = rtcAttachGeometry(world_->scene(), instance);
        rtcReleaseGeometry(instance);
        if (instance_placement_.size() <= id) instance_placement_.resize(id + 1, Hit::kNone);
        instance_placement_[id] = k;
    }

    /// Embree's memory monitor: the bytes its device holds, counted as it allocates and frees.
    static bool count_bytes(void* counter, ssize_t bytes, bool) {
        static_cast<std::atomic<ssize_t>*>(counter)->fetch_add(bytes);
        return true;
    }

    void release() {
        world_.reset();
        prototypes_.clear();
        rtcReleaseDevice(device_);
    }

    const Geometry& geometry_;
    RTCDevice device_ = nullptr;
    std::unique_ptr<EmbreeLevel> world_;
    std::vector<std::unique_ptr<EmbreeLevel>> prototypes_;
    std::vector<uint32_t> instance_placement_;  // Embree's instance geomID -> placement
    std::atomic<ssize_t> bytes_{0};
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

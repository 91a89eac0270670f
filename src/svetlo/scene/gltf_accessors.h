// glTF's accessors (glTF 2.0, 3.6): the typed, strided views of a buffer that hold a mesh's
// attributes and indices, read as numbers; sparse accessors included. Every element is
// checked to lie inside its buffer before one is read.
#pragma once

#include <tiny_gltf.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "svetlo/core/bytes.h"

namespace svetlo {

/// The elements of accessors with a buffer view (or of a sparse accessor's indices and values):
/// `components` numbers of `component_type` each, `stride` bytes apart.
class StridedView {
public:
    StridedView() = default;
    /// Checks that `count` elements from `byte_offset` into buffer view `view_index` lie
    /// inside that view and its buffer.
    StridedView(const tinygltf::Model& model, int view_index, size_t byte_offset, size_t count,
                int components, int component_type, bool normalized) {
        if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
            throw std::runtime_error("buffer view " + std::to_string(view_index) + " missing");
        const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(view_index)];
        if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
            throw std::runtime_error("buffer view without a buffer");
        const tinygltf::Buffer& buffer = model.buffers[static_cast<size_t>(view.buffer)];
        const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(component_type));
        if (size <= 0) throw std::runtime_error("unsupported component type");
        type_ = component_type;
        size_ = static_cast<size_t>(size);
        normalized_ = normalized;
        const size_t element = static_cast<size_t>(components) * size_;
        stride_ = view.byteStride > 0 ? view.byteStride : element;
        // Every element inside the buffer; the first inside its view.
        const size_t need = count == 0 ? 0 : byte_offset + stride_ * (count - 1) + element;
        if (view.byteOffset + need > buffer.data.size() ||
            byte_offset + element > view.byteLength + stride_)
            throw std::runtime_error("accessor runs past its buffer");
        data_ = buffer.data.data() + view.byteOffset + byte_offset;
    }

    double component(size_t index, int c) const {
        const unsigned char* p = data_ + index * stride_ + static_cast<size_t>(c) * size_;
        switch (type_) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT:
                return load<float>(p);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return normalized_ ? load<uint8_t>(p) / 255.0 : load<uint8_t>(p);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                return normalized_ ? load<uint16_t>(p) / 65535.0 : load<uint16_t>(p);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
                return load<uint32_t>(p);
            // Signed normalised: max(c / (2^(b-1) - 1), -1) (glTF 2.0, 3.11).
            case TINYGLTF_COMPONENT_TYPE_BYTE:
                return normalized_ ? std::max(load<int8_t>(p) / 127.0, -1.0) : load<int8_t>(p);
            case TINYGLTF_COMPONENT_TYPE_SHORT:
                return normalized_ ? std::max(load<int16_t>(p) / 32767.0, -1.0) : load<int16_t>(p);
            default:
                throw std::runtime_error("unsupported component type");
        }
    }

private:
    template <typename T>
    static double load(const unsigned char* p) {
        return static_cast<double>(load_bytes<T>(p));
    }
    const unsigned char* data_ = nullptr;
    size_t stride_ = 0, size_ = 0;
    int type_ = 0;
    bool normalized_ = false;
};

/// The most elements an accessor without a buffer view of its own (all zeros, or sparse
/// values on zeros) may have: such an accessor's count is not bounded by any buffer.
constexpr size_t kMaxDenseElements = size_t{1} << 24;

/// The components of a float accessor's elements (or a normalised or plain integer one's), as
/// numbers. A sparse accessor (glTF 2.0, 3.6.2.3) is its buffer view's elements, or zeros without
/// one, with the sparse values written over the elements its indices name.
class AccessorView {
public:
    AccessorView(const tinygltf::Model& model, int accessor_index, int components) {
        if (accessor_index < 0 || static_cast<size_t>(accessor_index) >= model.accessors.size()) {
            throw std::runtime_error("accessor " + std::to_string(accessor_index) + " missing");
        }
        const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(accessor_index)];
        const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
        if (n != components) throw std::runtime_error("unexpected accessor type");
        components_ = n;
        count_ = a.count;
        if (a.bufferView >= 0)
            view_ = StridedView(model, a.bufferView, a.byteOffset, a.count, n, a.componentType,
                                a.normalized);
        if (a.bufferView < 0 || a.sparse.isSparse) densify(model, a, accessor_index);
    }

    size_t count() const { return count_; }

    /// The number of components of accessor `index`'s type (3 for VEC3, ...), 0 when there
    /// is no such accessor.
    static int components_of(const tinygltf::Model& model, int index) {
        if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) return 0;
        return tinygltf::GetNumComponentsInType(
            static_cast<uint32_t>(model.accessors[static_cast<size_t>(index)].type));
    }

    double component(size_t index, int c) const {
        if (!dense_.empty()) return dense_[index * static_cast<size_t>(components_) + c];
        return view_.component(index, c);
    }

private:
    /// The accessor's elements, its sparse values written over them, into dense_.
    void densify(const tinygltf::Model& model, const tinygltf::Accessor& a, int index) {
        const std::string name = "accessor " + std::to_string(index);
        if (a.bufferView < 0 && count_ > kMaxDenseElements)
            throw std::runtime_error(name + ": " + std::to_string(count_) +
                                     " elements without a buffer view of their own (at most " +
                                     std::to_string(kMaxDenseElements) + ")");
        const auto n = static_cast<size_t>(components_);
        dense_.assign(count_ * n, 0.0);
        if (a.bufferView >= 0)
            for (size_t k = 0; k < count_; ++k)
                for (size_t c = 0; c < n; ++c) dense_[k * n + c] = view_.component(k, int(c));
        if (!a.sparse.isSparse) return;
        const int type = a.sparse.indices.componentType;
        if (a.sparse.count < 1 || static_cast<size_t>(a.sparse.count) > count_ ||
            a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0 ||
            (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            throw std::runtime_error(name + ": sparse count, offsets or index type wrong");
        const auto m = static_cast<size_t>(a.sparse.count);
        // Sparse views are tightly packed (glTF 2.0: their buffer views have no byteStride).
        const StridedView indices(model, a.sparse.indices.bufferView,
                                  static_cast<size_t>(a.sparse.indices.byteOffset), m, 1, type,
                                  false);
        const StridedView values(model, a.sparse.values.bufferView,
                                 static_cast<size_t>(a.sparse.values.byteOffset), m, components_,
                                 a.componentType, a.normalized);
        for (size_t k = 0; k < m; ++k) {
            const double at = indices.component(k, 0);
            if (!(at < static_cast<double>(count_)))
                throw std::runtime_error(name + ": sparse index out of range");
            for (size_t c = 0; c < n; ++c)
                dense_[static_cast<size_t>(at) * n + c] = values.component(k, int(c));
        }
    }

    StridedView view_;
    std::vector<double> dense_;  // every element, where the accessor is sparse or has no view
    size_t count_ = 0;
    int components_ = 0;
};

}  // namespace svetlo

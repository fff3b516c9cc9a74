#include "multi_view.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>

#include "wavecam/output_layout.h"

namespace wavecam::detail {
namespace {
namespace Strutil = OIIO::Strutil;

// A channel's view ("" for none) and its name without the view.
struct ViewedChannel {
    std::string view, plain;
};

ViewedChannel view_of(const std::string& name, const std::vector<std::string>& views) {
    const std::vector<std::string> parts = Strutil::splits(name, ".");
    if (parts.size() < 2) return {views.front(), name};
    const std::string& named = parts[parts.size() - 2];
    if (std::find(views.begin(), views.end(), named) == views.end()) return {"", name};
    std::vector<std::string> rest(parts.begin(), parts.end() - 2);
    rest.push_back(parts.back());
    return {named, Strutil::join(rest, ".")};
}

}  // namespace

std::vector<std::string> view_names(const OIIO::ImageSpec& spec) {
    std::vector<std::string> views;
    const OIIO::ParamValue* p = spec.find_attribute("multiView");
    if (!p || p->type().basetype != OIIO::TypeDesc::STRING) return views;
    const auto* names = static_cast<const OIIO::ustring*>(p->data());
    for (int k = 0; k < p->nvalues() * int(p->type().numelements()); ++k) views.push_back(names[k].string());
    if (views.size() < 2) views.clear();
    return views;
}

Result<bool> diffract_each_view(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name,
                                const DiffractOneView& one) {
    using Fail = Result<bool>;
    const OIIO::ImageSpec& in = src.spec();
    const std::vector<std::string> views = view_names(in);
    std::vector<ViewedChannel> placed;
    for (const std::string& n : in.channelnames) placed.push_back(view_of(n, views));

    // each view alone: its channels under their plain names, beside the channels of no view
    std::vector<OIIO::ImageBuf> results(views.size());
    for (size_t v = 0; v < views.size(); ++v) {
        std::vector<int> order;
        std::vector<std::string> names;
        for (int c = 0; c < in.nchannels; ++c)
            if (placed[c].view == views[v] || placed[c].view.empty()) {
                order.push_back(c);
                names.push_back(placed[c].plain);
            }
        OIIO::ImageBuf view;
        if (!OIIO::ImageBufAlgo::channels(view, src, int(order.size()), order.data(), nullptr, names.data()))
            return Fail::failure(name + ": cannot read view '" + views[v] + "': " + view.geterror());
        view.specmod().erase_attribute("multiView");
        if (auto r = one(results[v], view, name + " (view " + views[v] + ")"); !r.ok()) return r;
    }

    // every channel the results hold, under the input's names and in its order
    OIIO::ImageSpec spec = results.front().spec();
    spec.channelnames.clear();
    spec.alpha_channel = spec.z_channel = -1;
    struct From {
        size_t view;
        int channel;
    };
    std::vector<From> from;
    std::vector<std::string> diffracted;
    std::vector<std::vector<std::string>> done;  // each view's diffracted channels, by their plain names
    for (const OIIO::ImageBuf& r : results)
        done.push_back(Strutil::splits(r.spec().get_string_attribute(kDiffractedChannelsAttribute), ","));
    for (int c = 0; c < in.nchannels; ++c) {
        const size_t v = placed[c].view.empty() ? 0 : size_t(std::find(views.begin(), views.end(), placed[c].view) - views.begin());
        const OIIO::ImageSpec& r = results[v].spec();
        const int k = r.channelindex(placed[c].plain);
        if (k < 0) continue;  // dropped (the other-channels setting)
        if (v == 0 && k == r.alpha_channel) spec.alpha_channel = int(spec.channelnames.size());
        if (v == 0 && k == r.z_channel) spec.z_channel = int(spec.channelnames.size());
        if (std::find(done[v].begin(), done[v].end(), placed[c].plain) != done[v].end())
            diffracted.push_back(in.channelnames[c]);
        spec.channelnames.push_back(in.channelnames[c]);
        from.push_back({v, k});
    }
    spec.nchannels = int(spec.channelnames.size());
    spec.attribute(kDiffractedChannelsAttribute, Strutil::join(diffracted, ","));
    if (const OIIO::ParamValue* p = in.find_attribute("multiView")) spec.attribute(p->name(), p->type(), p->data());
    spec.attribute("wavecam.views", Strutil::join(views, ", ") + ": each view diffracted with its own depth");
    dst.reset(spec);
    const OIIO::stride_t pixel = spec.nchannels * sizeof(float), row = pixel * spec.width;
    for (size_t k = 0; k < from.size(); ++k) {
        const OIIO::ImageBuf& r = results[from[k].view];
        OIIO::ROI roi = r.roi();
        roi.chbegin = from[k].channel;
        roi.chend = roi.chbegin + 1;
        if (!r.get_pixels(roi, OIIO::TypeDesc::FLOAT, dst.pixeladdr(spec.x, spec.y, 0, int(k)), pixel, row))
            return Fail::failure(name + ": " + r.geterror());
    }
    return Fail::success(true);
}

}  // namespace wavecam::detail

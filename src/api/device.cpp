// ts::Device and the device list of tileshade.h, over ClContext.
#include "api/api_internal.h"

namespace ts {

std::vector<DeviceDescription> listDeviceDescriptions() {
  std::vector<DeviceDescription> out;
  for (const DeviceInfo& d : listDevices()) {
    DeviceDescription o;
    o.index = d.index;
    o.platform = d.platform;
    o.name = d.name;
    o.type = d.type;
    o.computeUnits = d.computeUnits;
    o.globalMemBytes = d.globalMemBytes;
    o.localMemBytes = d.localMemBytes;
    out.push_back(o);
  }
  return out;
}

Device::Device(const std::string& spec)
    : impl_(openclErrorsAsTs([&] { return std::make_shared<Impl>(spec); })) {}

Device Device::fromOpenCL(cl_context context, cl_device_id device, cl_command_queue queue) {
  return Device(openclErrorsAsTs([&] { return std::make_shared<Impl>(context, device, queue); }));
}

std::string Device::name() const { return impl_->cl.deviceName(); }
std::string Device::type() const { return impl_->cl.info().type; }
double Device::compileMs() const { return impl_->cl.compileMs(); }

}  // namespace ts

# Lumen in a container, for batch engines (docs/src/scale-out.md): the `lumen` binary on
# Debian with Mesa's lavapipe (Vulkan on the CPU), so nodes without a GPU render.
# Untested here (no registry to pull the base images from); see docs/src/scale-out.md.
FROM rust:1.95-bookworm AS build
WORKDIR /src
COPY . .
RUN cargo build --release --bin lumen

FROM debian:bookworm-slim
RUN apt-get update \
    && apt-get install -y --no-install-recommends \
       mesa-vulkan-drivers libvulkan1 libegl1 libegl-mesa0 libgl1-mesa-dri \
    && rm -rf /var/lib/apt/lists/*
COPY --from=build /src/target/release/lumen /usr/local/bin/lumen
# The built-in scenes find their assets under the working directory.
COPY assets /opt/lumen/assets
WORKDIR /opt/lumen
ENTRYPOINT ["lumen"]

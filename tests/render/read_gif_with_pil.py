"""Independent reader of framequake's GIF animations for the render tests.

Usage: read_gif_with_pil.py GIF [RAW_FOLDER]
Prints JSON {"n_frames", "width", "height", "loop", "durations_ms"}; with
RAW_FOLDER, also writes each frame as RGB bytes (rows top to bottom) to
RAW_FOLDER/frame_NNNNNN.rgb. Uses Pillow (Debian python3-pil), whose GIF
decoder shares no code with framequake's encoder.
"""
import json
import os
import sys

from PIL import Image, ImageSequence


def main(path, raw_folder=None):
    with Image.open(path) as im:
        if im.format != "GIF":
            sys.exit("not a GIF: " + str(im.format))
        out = {"width": im.width, "height": im.height, "loop": im.info.get("loop"), "durations_ms": []}
        n = 0
        for frame in ImageSequence.Iterator(im):
            out["durations_ms"].append(frame.info.get("duration"))
            if raw_folder:
                with open(os.path.join(raw_folder, "frame_%06d.rgb" % n), "wb") as f:
                    f.write(frame.convert("RGB").tobytes())
            n += 1
        out["n_frames"] = n
    print(json.dumps(out))


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: read_gif_with_pil.py GIF [RAW_FOLDER]")
    main(*sys.argv[1:])

"""A test executor that writes to stdout every way it can: print, sys.stdout, the file descriptor
(as native code does), and print after serving; only answers may reach its stdout. With
SLOW_AT=N it sleeps long at road N (to be stopped by a signal); close() says so on stderr."""

import os
import sys
import time

import wogan


class Noisy(wogan.Executor):
    def drive(self, road):
        print(f"print at road {road.id}")
        sys.stdout.write("sys.stdout at road {}\n".format(road.id))
        os.write(1, b"file descriptor 1\n")
        if road.id == int(os.environ.get("SLOW_AT", "0")):
            print("slow road", flush=True)
            time.sleep(60)
        return wogan.Answer(max_bolp=0.5)

    def close(self):
        print("closed", file=sys.stderr, flush=True)


Noisy().serve()
print("after serve")
os.write(1, b"after serve, file descriptor 1\n")

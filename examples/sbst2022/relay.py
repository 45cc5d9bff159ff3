"""wogan's executor for wogan_generator.py: copies the lines wogan writes to the roads pipe and the
generator's answers back to wogan. It ends when wogan closes its input.

    python3 relay.py ROADS_FIFO ANSWERS_FIFO
"""
import sys
import threading

roads = open(sys.argv[1], "w")
answers = open(sys.argv[2])


def forward_roads():
    for line in sys.stdin:
        roads.write(line)
        roads.flush()
    roads.close()


threading.Thread(target=forward_roads, daemon=True).start()
for line in answers:
    sys.stdout.write(line)
    sys.stdout.flush()

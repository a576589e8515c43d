"""This process on the ROS 2 DDS graph: one Cyclone DDS participant, its writers and readers.

The domain is ``ROS_DOMAIN_ID`` (0 when unset), as for every ROS 2 node;
Cyclone DDS reads its own configuration (network interface, peers,
multicast) from ``CYCLONEDDS_URI``. A ROS name ``/robot_0/odom`` is the DDS
topic ``rt/robot_0/odom`` (ROS 2's "Topic and Service name mapping to DDS").
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

from cyclonedds.core import Listener
from cyclonedds.domain import DomainParticipant
from cyclonedds.internal import InvalidSample
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from mimics.world.errors import MimicsError

DOMAIN_VARIABLE = "ROS_DOMAIN_ID"
MAX_DOMAIN = 232  # DDS's RTPS port mapping leaves room for domains 0 to 232
_TAKE = 64  # samples taken per call of a reader's callback


def domain_id(environ: dict[str, str] | None = None) -> int:
    """The DDS domain of ``ROS_DOMAIN_ID`` (0 when unset or empty).

    Raises:
        MimicsError: naming ``ROS_DOMAIN_ID`` when it is not a whole number 0 to 232.
    """
    text = (os.environ if environ is None else environ).get(DOMAIN_VARIABLE, "").strip()
    if not text:
        return 0
    if not text.isdigit() or int(text) > MAX_DOMAIN:
        raise MimicsError(f"{DOMAIN_VARIABLE}: expected a whole number from 0 to {MAX_DOMAIN}, "
                          f"got {text!r}")
    return int(text)


def dds_topic(ros_name: str) -> str:
    """The DDS topic of a ROS 2 topic: ``/robot_0/odom`` gives ``rt/robot_0/odom``."""
    return "rt/" + ros_name.lstrip("/")


def service_topics(ros_name: str) -> tuple[str, str]:
    """The DDS topics of a ROS 2 service's requests and replies: ``/mimics/pause`` gives
    ``rq/mimics/pauseRequest`` and ``rr/mimics/pauseReply``."""
    name = ros_name.lstrip("/")
    return f"rq/{name}Request", f"rr/{name}Reply"


class DdsGraph:
    """A participant in ``domain`` and every topic, writer and reader made through it."""

    def __init__(self, domain: int) -> None:
        try:
            self.participant = DomainParticipant(domain)
        except Exception as exc:  # a bad CYCLONEDDS_URI, no usable interface
            raise MimicsError(f"Cyclone DDS could not join domain {domain} ({exc}); check "
                              "CYCLONEDDS_URI and ROS_DOMAIN_ID") from None
        self._topics: dict[str, Topic] = {}
        self._entities: list[Any] = []

    def _topic(self, name: str, kind: type) -> Topic:
        topic = self._topics.get(name)
        if topic is None:
            topic = self._topics[name] = Topic(self.participant, name, kind)
        return topic

    def writer(self, ros_name: str, kind: type, qos: Qos,
               dds_name: str | None = None) -> DataWriter:
        """A writer of ``kind`` messages on the ROS topic ``ros_name`` (or, given, the DDS
        topic ``dds_name``)."""
        topic = self._topic(dds_name or dds_topic(ros_name), kind)
        writer = DataWriter(self.participant, topic, qos=qos)
        self._entities.append(writer)
        return writer

    def reader(self, ros_name: str, kind: type, qos: Qos, on_sample: Callable[[Any], None],
               dds_name: str | None = None) -> DataReader:
        """A reader of ``ros_name`` (or, given, the DDS topic ``dds_name``) calling
        ``on_sample`` with each message, on Cyclone's receiving thread."""

        def available(reader: DataReader) -> None:
            for sample in reader.take(_TAKE):
                if not isinstance(sample, InvalidSample):  # a writer's going, not data
                    on_sample(sample)

        topic = self._topic(dds_name or dds_topic(ros_name), kind)
        reader = DataReader(self.participant, topic, qos=qos,
                            listener=Listener(on_data_available=available))
        self._entities.append(reader)
        return reader

    def close(self) -> None:
        """Withdraw every reader and writer, then leave the domain."""
        for entity in (*reversed(self._entities), *self._topics.values(), self.participant):
            entity.__del__()  # deleted now (the readers' callbacks stop), not when collected
        self._entities, self._topics = [], {}


def matched_readers(writer: DataWriter) -> int:
    """How many readers the writer has matched."""
    return len(writer.get_matched_subscriptions())


def matched_writers(reader: DataReader) -> int:
    """How many writers the reader has matched."""
    return len(reader.get_matched_publications())

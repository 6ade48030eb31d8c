#[cfg(any(feature = "mio_06", feature = "mio_1"))]
use std::io;

#[cfg(feature = "mio_06")]
use rustdds::mio::{Evented, Poll, PollOpt, Ready, Token};
#[cfg(feature = "mio_1")]
use rustdds::mio1;
use rustdds::{rpc::*, *};
#[allow(unused_imports)]
use log::{debug, error, info, warn};
use futures::{StreamExt, pin_mut, stream::FusedStream};
use std::{
  collections::BTreeMap,
  sync::{Arc, Mutex},
  time::{Duration, Instant},
};

use crate::{
  error::{CreateResult, ReadError, ReadResult, WriteError, WriteResult},
  message::Message,
  message_info::MessageInfo,
  node::{MatchOrdinals, Node},
  qos::QosProfile,
  service::*,
};

// --------------------------------------------
// --------------------------------------------
/// Server end of a ROS2 Service
pub struct Server<Req, Resp>
where
  Req: Message,
  Resp: Message,
{
  service_mapping: ServiceMapping,
  request_receiver: SimpleDataReaderR<RequestWrapper<Req>>,
  response_sender: DataWriterR<ResponseWrapper<Resp>>,
  // motion-suite patch: see `wait_for_requester`.
  matches: Matches,
  requesters: Mutex<BTreeMap<RmwRequestId, GUID>>,
}

/// motion-suite patch: longest a reply waits for the requester's reply reader
/// to be matched (rmw_fastrtps and rmw_cyclonedds wait likewise). 500 ms lost a
/// fresh participant's first reply once in a loaded test run (discovery of its
/// reader took longer); an unmatched reply is lost for good, a late one is not.
pub const REPLY_MATCH_WAIT: Duration = Duration::from_secs(3);

/// Requests whose requester is remembered; beyond this the oldest are
/// forgotten (their replies then go out without waiting).
const MAX_REMEMBERED_REQUESTERS: usize = 16_384;

/// The matches the reply wait looks at: the order in which the reply writer matched
/// remote readers and the request reader remote writers, as the node's spinner keeps
/// it.
#[derive(Clone)]
struct Matches {
  ordinals: Arc<Mutex<MatchOrdinals>>,
  reply_writer: GUID,
  request_reader: GUID,
}

impl Matches {
  /// True when the reply writer has matched the requester's reply reader: the
  /// request writer is its participant's k-th (see [`MatchOrdinals`]) and the reply
  /// writer has matched k readers of that participant.
  fn requester_matched(&self, requester: GUID) -> bool {
    let m = self.ordinals.lock().unwrap();
    let k = m.ordinal(self.request_reader, requester);
    m.total(self.reply_writer, requester) >= k
  }
}

impl<Req, Resp> Server<Req, Resp>
where
  Req: Message + 'static,
  Resp: Message + 'static,
{
  pub(crate) fn new(
    service_mapping: ServiceMapping,
    node: &mut Node,
    request_topic: &Topic,
    response_topic: &Topic,
    qos_request: Option<QosProfile>,
    qos_response: Option<QosProfile>,
  ) -> CreateResult<Self> {
    let request_receiver =
      node.create_simpledatareader
      ::<RequestWrapper<Req>, ServiceDeserializerAdapter<RequestWrapper<Req>>>(
        request_topic, qos_request)?;
    let response_sender = node
      .create_datawriter::<ResponseWrapper<Resp>, ServiceSerializerAdapter<ResponseWrapper<Resp>>>(
        response_topic,
        qos_response,
      )?;

    debug!(
      "Created new Server: requests={} response={}",
      request_topic.name(),
      response_topic.name()
    );

    let matches = Matches {
      ordinals: node.match_ordinals(),
      reply_writer: response_sender.guid(),
      request_reader: request_receiver.guid(),
    };
    Ok(Server::<Req, Resp> {
      service_mapping,
      request_receiver,
      response_sender,
      matches,
      requesters: Mutex::new(BTreeMap::new()),
    })
  }

  /// Remembers the participant of a request's writer (its reply reader lives
  /// there).
  fn note_requester(&self, id: RmwRequestId, mi: &MessageInfo) {
    let mut m = self.requesters.lock().unwrap();
    if m.len() >= MAX_REMEMBERED_REQUESTERS {
      m.pop_first();
    }
    m.insert(id, GUID::from(mi.publisher_gid()));
  }

  /// Forgets the requester of `id` (its reply goes out without waiting).
  fn forget_requester(&self, id: RmwRequestId) {
    self.requesters.lock().unwrap().remove(&id);
  }

  /// motion-suite patch: waits (at most [`REPLY_MATCH_WAIT`]) until the reply
  /// writer has matched a reader of the participant that sent request `id`.
  /// A fresh client sends its request as soon as *it* sees the server's
  /// endpoints; this server may not have discovered the client's reply reader
  /// yet, and a volatile reply written before that match never reaches it: the
  /// first call of every fresh participant (each `ros2 service call`) was lost
  /// or answered only at a later heartbeat. Returns at once when matched.
  pub async fn wait_for_requester(&self, id: RmwRequestId) {
    let Some(requester) = self.requesters.lock().unwrap().remove(&id) else {
      return;
    };
    if self.matches.requester_matched(requester) {
      return;
    }
    let matches = self.matches.clone();
    let (tx, rx) = futures::channel::oneshot::channel::<()>();
    // No timer in this crate's runtime-agnostic API: a short-lived thread polls.
    std::thread::spawn(move || {
      let end = Instant::now() + REPLY_MATCH_WAIT;
      while !matches.requester_matched(requester) && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(1));
      }
      let _ = tx.send(());
    });
    let _ = rx.await;
    if !self.matches.requester_matched(requester) {
      debug!("reply to {id:?}: requester's reader not matched, sending anyway");
    }
  }

  /// Receive a request from Client.
  /// Returns `Ok(None)` if no new requests have arrived.
  pub fn receive_request(&self) -> ReadResult<Option<(RmwRequestId, Req)>> {
    self.request_receiver.drain_read_notifications();
    let dcc_rw: Option<no_key::DeserializedCacheChange<RequestWrapper<Req>>> =
      self.request_receiver.try_take_one()?;

    match dcc_rw {
      None => Ok(None),
      Some(dcc) => {
        let mi = MessageInfo::from(&dcc);
        let req_wrapper = dcc.into_value();
        let (ri, req) = req_wrapper.unwrap(self.service_mapping, &mi)?;
        self.note_requester(ri, &mi);
        Ok(Some((ri, req)))
      }
    } // match
  }

  /// Send response to request by Client.
  /// rmw_req_id identifies request being responded.
  /// (motion-suite patch) Does not wait for the requester's reader; see
  /// [`Self::async_send_response`].
  pub fn send_response(&self, rmw_req_id: RmwRequestId, response: Resp) -> WriteResult<(), ()> {
    self.forget_requester(rmw_req_id);
    let resp_wrapper = ResponseWrapper::<Resp>::new(
      self.service_mapping,
      rmw_req_id,
      RepresentationIdentifier::CDR_LE,
      response,
    )?;
    let write_opts = WriteOptionsBuilder::new()
      .source_timestamp(Timestamp::now()) // always add source timestamp
      .related_sample_identity(SampleIdentity::from(rmw_req_id))
      // TODO: Check if this is right. Cyclone mapping does not send
      // Related Sample Identity in
      // WriteOptions (QoS ParameterList), but within data payload.
      // But maybe it is not harmful to send it in both?
      .build();
    self
      .response_sender
      .write_with_options(resp_wrapper, write_opts)
      .map(|_| ())
      .map_err(|e| WriteError::from(e.forget_data())) // lose SampleIdentity
    // result
  }

  /// The request_id must be sent back with the response to identify which
  /// request and response belong together.
  pub async fn async_receive_request(&self) -> ReadResult<(RmwRequestId, Req)> {
    let dcc_stream = self.request_receiver.as_async_stream();
    pin_mut!(dcc_stream);

    match dcc_stream.next().await {
      Some(Err(e)) => Err(e.into()),
      Some(Ok(dcc)) => {
        let mi = MessageInfo::from(&dcc);
        let req_wrapper = dcc.into_value();
        let (ri, req) = req_wrapper.unwrap(self.service_mapping, &mi)?;
        self.note_requester(ri, &mi);
        debug!("async_receive_request: {ri:?}");
        Ok((ri, req))
      }
      // This should never occur, because topic do not "end".
      None => read_error_internal!("SimpleDataReader value stream unexpectedly ended!"),
    } // match
  }

  /// Returns a never-ending stream of (request_id, request)
  /// The request_id must be sent back with the response to identify which
  /// request and response belong together.
  pub fn receive_request_stream(
    &self,
  ) -> impl FusedStream<Item = ReadResult<(RmwRequestId, Req)>> + '_ {
    Box::pin(self.request_receiver.as_async_stream().then(
      move |dcc_r| async move {
        match dcc_r {
          Err(e) => Err(e.into()),
          Ok(dcc) => {
            let mi = MessageInfo::from(&dcc);
            let req_wrapper = dcc.into_value();
            debug!("receive_request_stream: messageinfo={mi:?}");
            let r = req_wrapper.unwrap(self.service_mapping, &mi);
            if let Ok((ri, _)) = &r {
              self.note_requester(*ri, &mi);
            }
            r
          }
        } // match
      }, // async
    ))
  }

  /// Asynchronous response sending
  pub async fn async_send_response(
    &self,
    rmw_req_id: RmwRequestId,
    response: Resp,
  ) -> WriteResult<(), ()> {
    self.wait_for_requester(rmw_req_id).await;
    let resp_wrapper = ResponseWrapper::<Resp>::new(
      self.service_mapping,
      rmw_req_id,
      RepresentationIdentifier::CDR_LE,
      response,
    )?;
    debug!("async_send_response: rmw_req_id = {rmw_req_id:?}");
    debug!(
      "async_send_response: related_sample_identity = {:?}",
      SampleIdentity::from(rmw_req_id)
    );
    let write_opts = WriteOptionsBuilder::new()
      .source_timestamp(Timestamp::now()) // always add source timestamp
      .related_sample_identity(SampleIdentity::from(rmw_req_id))
      // TODO: Check if this is right. Cyclone mapping does not send
      // Related Sample Identity in
      // WriteOptions (QoS ParameterList), but within data payload.
      // But maybe it is not harmful to send it in both?
      .build();
    self
      .response_sender
      .async_write_with_options(resp_wrapper, write_opts)
      .await
      .map(|_| ())
      .map_err(|e| WriteError::from(e.forget_data())) // lose SampleIdentity
    // result
  }
}

#[cfg(feature = "mio_06")]
impl<Req, Resp> Evented for Server<Req, Resp>
where
  Req: Message + 'static,
  Resp: Message + 'static,
{
  fn register(&self, poll: &Poll, token: Token, interest: Ready, opts: PollOpt) -> io::Result<()> {
    self.request_receiver.register(poll, token, interest, opts)
  }

  fn reregister(
    &self,
    poll: &Poll,
    token: Token,
    interest: Ready,
    opts: PollOpt,
  ) -> io::Result<()> {
    self
      .request_receiver
      .reregister(poll, token, interest, opts)
  }

  fn deregister(&self, poll: &Poll) -> io::Result<()> {
    self.request_receiver.deregister(poll)
  }
}

#[cfg(feature = "mio_1")]
impl<Req, Resp> mio1::event::Source for Server<Req, Resp>
where
  Req: Message + 'static,
  Resp: Message + 'static,
{
  fn register(
    &mut self,
    registry: &mio1::Registry,
    token: mio1::Token,
    interests: mio1::Interest,
  ) -> io::Result<()> {
    mio1::event::Source::register(&mut self.request_receiver, registry, token, interests)
  }

  fn reregister(
    &mut self,
    registry: &mio1::Registry,
    token: mio1::Token,
    interests: mio1::Interest,
  ) -> io::Result<()> {
    mio1::event::Source::reregister(&mut self.request_receiver, registry, token, interests)
  }

  fn deregister(&mut self, registry: &mio1::Registry) -> io::Result<()> {
    mio1::event::Source::deregister(&mut self.request_receiver, registry)
  }
}

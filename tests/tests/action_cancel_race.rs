//! A cancel request that races with the goal's end (regression test of the ros2-client patch
//! "a cancel never moves an ended goal back", vendor/README.md). Our nodes end a goal as soon
//! as the engine takes the halt over, which can be before the cancel is answered; the server
//! then set the ended goal to CANCELING and panicked at the next goal (`Flushing goal with
//! wrong status: Canceling`), after which the action was deaf.

use motion_msgs::action::{
    MoveAbsolute as MoveAbsoluteAction, MoveAbsoluteFeedback, MoveAbsoluteGoal, MoveAbsoluteResult,
};
use motion_runtime::shell::action_server_qos;
use ros2_client::action::{AsyncActionServer, GoalEndStatus};
use ros2_client::action_msgs::{CancelGoalResponseEnum, GoalStatusEnum};
use ros2_client::builtin_interfaces::Time;
use ros2_client::ServiceMapping;
use system_tests::{require_netns, unique_domain, within, ClientNode};

type Server = AsyncActionServer<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>;

/// Goal 1 ends CANCELED and goal 2 SUCCEEDED between the server's reading of their cancel
/// requests and its answer. Goal 1 is reported canceling (its cancel did end it), goal 2
/// GOAL_TERMINATED with no goal listed; both keep their end status, and goal 3 is served.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_cancel_answered_after_the_goal_ended_keeps_the_end_status() {
    require_netns();
    let domain = unique_domain();
    let mut server_node = ClientNode::new(domain, "race_server", ServiceMapping::Cyclone);
    let server: Server = AsyncActionServer::new(
        server_node
            .node
            .create_action_server(
                ServiceMapping::Cyclone,
                &ClientNode::name("/race/move"),
                &MoveAbsoluteAction::action_type_name(),
                action_server_qos(),
            )
            .expect("action server"),
    );
    let mut client_node = ClientNode::new(domain, "race_client", ServiceMapping::Cyclone);
    let client = client_node
        .action::<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>(
            "/race/move",
            &MoveAbsoluteAction::action_type_name(),
        )
        .await;
    let serve_results = async {
        let _ = server.serve_result_requests().await;
    };

    let scenario = async {
        for (k, end) in [GoalEndStatus::Canceled, GoalEndStatus::Succeeded]
            .into_iter()
            .enumerate()
        {
            // The goal is accepted and executing.
            let serve_goal = async {
                let new = server.receive_new_goal().await.expect("goal request");
                assert!(server.get_new_goal(new.clone()).is_some());
                let accepted = server.accept_goal(new).await.expect("accept");
                server
                    .start_executing_goal(accepted)
                    .await
                    .expect("execute")
            };
            let ((gid, resp), executing) = tokio::join!(
                async {
                    client
                        .async_send_goal(MoveAbsoluteGoal::default())
                        .await
                        .unwrap()
                },
                serve_goal
            );
            assert!(resp.accepted, "goal {k}");
            // The cancel is read while the goal executes; the goal ends before the answer.
            let serve_cancel = async {
                let cancel = server
                    .receive_cancel_request()
                    .await
                    .expect("cancel request");
                assert!(cancel.contains_goal(&gid), "goal {k}");
                server
                    .send_result_response(executing, end, MoveAbsoluteResult::default())
                    .await
                    .expect("result");
                let listed: Vec<_> = cancel.goals().collect();
                server
                    .respond_to_cancel_requests(&cancel, listed.into_iter())
                    .await
                    .expect("cancel response");
            };
            let (answer, ()) = tokio::join!(
                async { client.async_cancel_goal(gid, Time::ZERO).await.unwrap() },
                serve_cancel
            );
            let (status, _) = within(10.0, "result", client.async_request_result(gid))
                .await
                .unwrap();
            match end {
                GoalEndStatus::Canceled => {
                    assert_eq!(answer.return_code, CancelGoalResponseEnum::None);
                    assert_eq!(answer.goals_canceling.len(), 1);
                    assert_eq!(answer.goals_canceling[0].goal_id, gid);
                    assert_eq!(status, GoalStatusEnum::Canceled);
                }
                _ => {
                    assert_eq!(answer.return_code, CancelGoalResponseEnum::GoalTerminated);
                    assert!(answer.goals_canceling.is_empty());
                    assert_eq!(status, GoalStatusEnum::Succeeded);
                }
            }
        }
        // Goal 3: the server flushes the ended goals (this panicked) and serves it.
        let serve_goal = async {
            let new = server.receive_new_goal().await.expect("goal request");
            assert!(server.get_new_goal(new.clone()).is_some());
            server.accept_goal(new).await.expect("accept");
        };
        let ((_, resp), ()) = tokio::join!(
            async {
                client
                    .async_send_goal(MoveAbsoluteGoal::default())
                    .await
                    .unwrap()
            },
            serve_goal
        );
        assert!(resp.accepted);
    };
    within(60.0, "cancel race scenario", async {
        tokio::select! {
            () = scenario => {}
            () = serve_results => panic!("result service ended"),
        }
    })
    .await;
}
